// Shared by the reference generators that read a fixture themselves (subdivision.cc,
// decimation.cc): the fixture reader, building an OpenMesh mesh from it, and writing the
// raw reference files. Header-only, `inline`, so that build.sh's one compile of every
// *.cc stays as it is.
#pragma once

#include <OpenMesh/Core/Geometry/VectorT.hh>

#include <cerrno>
#include <cstdint>
#include <fstream>
#include <stdexcept>
#include <string>
#include <sys/stat.h>
#include <vector>

namespace ref_io {

[[noreturn]] inline void fail(const std::string& message) { throw std::runtime_error(message); }

struct Input {
  std::vector<OpenMesh::Vec3d> positions;
  std::vector<std::vector<int32_t>> faces;
};

// The binary little-endian double PLY layout that openmesh_ref.cc's read_ply accepts.
inline Input read_ply(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("cannot open " + path);
  std::string line;
  std::vector<std::string> header;
  while (std::getline(in, line)) {
    if (line.rfind("comment", 0) == 0 || line.rfind("obj_info", 0) == 0) continue;
    header.push_back(line);
    if (line == "end_header") break;
  }
  const std::vector<std::string> want = {
      "ply",
      "format binary_little_endian 1.0",
      "element vertex ",
      "property double x",
      "property double y",
      "property double z",
      "element face ",
      "property list",
      "end_header"};
  if (header.size() != want.size()) fail(path + ": unexpected PLY header");
  for (size_t i = 0; i < want.size(); ++i)
    if (header[i].rfind(want[i], 0) != 0) fail(path + ": unexpected PLY header line " + header[i]);
  if (header[7] != "property list uchar int vertex_indices" &&
      header[7] != "property list uint8 int32 vertex_indices")
    fail(path + ": unexpected face property " + header[7]);
  const long n_vertices = std::stol(header[2].substr(want[2].size()));
  const long n_faces = std::stol(header[6].substr(want[6].size()));
  if (n_vertices < 0 || n_faces < 0) fail(path + ": negative element count");

  Input data;
  data.positions.resize(n_vertices);
  for (long v = 0; v < n_vertices; ++v) {
    double xyz[3];
    if (!in.read(reinterpret_cast<char*>(xyz), sizeof xyz)) fail(path + ": truncated vertices");
    data.positions[v] = OpenMesh::Vec3d(xyz[0], xyz[1], xyz[2]);
  }
  data.faces.resize(n_faces);
  for (long f = 0; f < n_faces; ++f) {
    unsigned char k;
    if (!in.read(reinterpret_cast<char*>(&k), 1)) fail(path + ": truncated faces");
    data.faces[f].resize(k);
    if (!in.read(reinterpret_cast<char*>(data.faces[f].data()), 4 * k))
      fail(path + ": truncated faces");
    for (int32_t j : data.faces[f])
      if (j < 0 || j >= n_vertices) fail(path + ": face index out of range");
  }
  return data;
}

template <class Mesh>
Mesh build_mesh(const Input& data) {
  Mesh mesh;
  std::vector<typename Mesh::VertexHandle> vh;
  for (const auto& p : data.positions) vh.push_back(mesh.add_vertex(p));
  for (size_t f = 0; f < data.faces.size(); ++f) {
    std::vector<typename Mesh::VertexHandle> face;
    for (int32_t i : data.faces[f]) face.push_back(vh[i]);
    if (!mesh.add_face(face).is_valid()) fail("OpenMesh rejected face " + std::to_string(f));
  }
  return mesh;
}

inline void make_dir(const std::string& path) {
  if (mkdir(path.c_str(), 0755) != 0 && errno != EEXIST) fail("cannot create " + path);
}

inline void write_file(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) fail("cannot write " + path);
}

inline void check_little_endian() {
  const uint16_t probe = 1;
  if (*reinterpret_cast<const unsigned char*>(&probe) != 1) fail("big-endian host");
}

}  // namespace ref_io

// OpenMesh's quadric-error decimation on a fixture: OpenMesh::Decimater::DecimaterT with
// ModQuadricT alone, in priority mode (unset_max_err(): no error bound, the cheapest
// halfedge collapse first), run from a fresh copy of the input for each ratio as
// `decimater.decimate_to(target)` followed by garbage_collection(). ModQuadricT sums,
// per vertex, the face-plane quadrics of its triangles weighted by their areas; the
// priority of a halfedge collapse v0 -> v1 is (Q0 + Q1)(p1), the kept vertex stays.
//
// Writes into OUTPUT_DIR/decimation/:
//
//   cases.txt                  one line per case: PERCENT TARGET VERTICES FACES, where
//                              TARGET = round(PERCENT / 100 * input vertices)
//   ratio_<percent>.f64        the decimated positions, 3 raw little-endian doubles per
//                              vertex, in OpenMesh's vertex order after garbage collection
//   ratio_<percent>.faces.u32  the faces, 3 raw little-endian uint32 per face: the
//                              targets of halfedge_handle(f), its next and next-next
//
// A fixture with a face that is not a triangle gets no decimation folder. The input is
// read exactly as openmesh_ref.cc reads it (binary little-endian double PLY, built with
// add_vertex/add_face).

#include "decimation.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#pragma GCC diagnostic pop

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <sys/stat.h>
#include <vector>

namespace {

struct DecimationTraits : public OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
  VertexAttributes(OpenMesh::Attributes::Status);
  EdgeAttributes(OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Status);
};
typedef OpenMesh::TriMesh_ArrayKernelT<DecimationTraits> Mesh;

// The ratios written, in percent of the input's vertices.
const int kPercents[] = {25, 50};

[[noreturn]] void fail(const std::string& message) { throw std::runtime_error(message); }

struct Input {
  std::vector<OpenMesh::Vec3d> positions;
  std::vector<std::vector<int32_t>> faces;
};

// The binary little-endian double PLY layout that openmesh_ref.cc's read_ply accepts.
Input read_ply(const std::string& path) {
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

Mesh build_mesh(const Input& data) {
  Mesh mesh;
  std::vector<Mesh::VertexHandle> vh;
  for (const auto& p : data.positions) vh.push_back(mesh.add_vertex(p));
  for (size_t f = 0; f < data.faces.size(); ++f) {
    std::vector<Mesh::VertexHandle> face;
    for (int32_t i : data.faces[f]) face.push_back(vh[i]);
    if (!mesh.add_face(face).is_valid()) fail("OpenMesh rejected face " + std::to_string(f));
  }
  return mesh;
}

void make_dir(const std::string& path) {
  if (mkdir(path.c_str(), 0755) != 0 && errno != EEXIST) fail("cannot create " + path);
}

void write_file(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) fail("cannot write " + path);
}

void check_little_endian() {
  const uint16_t probe = 1;
  if (*reinterpret_cast<const unsigned char*>(&probe) != 1) fail("big-endian host");
}

// Decimates a fresh copy of `input` to `target` vertices and writes it; returns its line
// of cases.txt.
std::string write_case(const Input& input, const std::string& dir, int percent, size_t target) {
  Mesh mesh = build_mesh(input);
  typedef OpenMesh::Decimater::DecimaterT<Mesh> Decimater;
  typedef OpenMesh::Decimater::ModQuadricT<Mesh>::Handle Quadric;
  Decimater decimater(mesh);
  Quadric quadric;
  if (!decimater.add(quadric)) fail("DecimaterT refused ModQuadricT");
  decimater.module(quadric).unset_max_err();
  if (!decimater.initialize()) fail("DecimaterT did not initialise");
  decimater.decimate_to(target);
  mesh.garbage_collection();

  std::string xyz;
  for (const auto& v : mesh.vertices()) {
    const OpenMesh::Vec3d p = mesh.point(v);
    xyz.append(reinterpret_cast<const char*>(p.data()), 3 * sizeof(double));
  }
  std::string tri;
  for (const auto& f : mesh.faces()) {
    Mesh::HalfedgeHandle h = mesh.halfedge_handle(f);
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = static_cast<uint32_t>(mesh.to_vertex_handle(h).idx());
      tri.append(reinterpret_cast<const char*>(&v), sizeof v);
      h = mesh.next_halfedge_handle(h);
    }
    if (h != mesh.halfedge_handle(f)) fail("decimation produced a face that is not a triangle");
  }
  const std::string stem = dir + "/ratio_" + std::to_string(percent);
  write_file(stem + ".f64", xyz);
  write_file(stem + ".faces.u32", tri);
  std::ostringstream line;
  line << percent << ' ' << target << ' ' << mesh.n_vertices() << ' ' << mesh.n_faces() << '\n';
  return line.str();
}

}  // namespace

void write_decimation(const std::string& input_ply, const std::string& out_dir) {
  check_little_endian();
  const Input data = read_ply(input_ply);
  for (const auto& face : data.faces)
    if (face.size() != 3) return;

  const std::string dir = out_dir + "/decimation";
  make_dir(out_dir);
  make_dir(dir);
  std::string cases;
  for (int percent : kPercents) {
    const size_t target = static_cast<size_t>(
        std::llround(static_cast<double>(percent) / 100.0 * static_cast<double>(data.positions.size())));
    cases += write_case(data, dir, percent, target);
  }
  write_file(dir + "/cases.txt", cases);
}

// OpenMesh's uniform subdivision on a fixture: OpenMesh::Subdivider::Uniform::LoopT and
// Sqrt3T, 1 and 2 steps, each run from a fresh copy of the input as one call
// `subdivider(mesh, steps)` (so a 2-step √3 run has an even and an odd step).
//
// Writes into OUTPUT_DIR/subdivision/:
//
//   cases.txt                  one line per written case: SCHEME STEPS VERTICES FACES
//   <scheme>_<steps>.f64       the subdivided positions, 3 raw little-endian doubles
//                              per vertex, in OpenMesh's vertex order
//   <scheme>_<steps>.faces.u32 the faces, 3 raw little-endian uint32 per face: the
//                              targets of halfedge_handle(f), its next and next-next
//
// A case is written only if its result has at most kMaxFaces faces, which keeps the
// references of all fixtures small; larger fixtures get only their smaller cases (or
// none). A fixture with a face that is not a triangle gets no subdivision folder.
//
// The input is read exactly as openmesh_ref.cc reads it (binary little-endian double
// PLY, built with add_vertex/add_face), so OpenMesh's vertex, edge and face numbering
// of the input is the one openmesh_ref.cc's topology.txt records.

#include "subdivision.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/Sqrt3T.hh>

#include <cerrno>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <sys/stat.h>
#include <vector>

namespace {

struct DoubleTraits : public OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};
typedef OpenMesh::TriMesh_ArrayKernelT<DoubleTraits> Mesh;

const int kSteps[] = {1, 2};
const size_t kMaxFaces = 12500;

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

// The number of faces after `steps` steps: both schemes multiply it per step.
size_t faces_after(size_t n_faces, int steps, size_t factor) {
  size_t n = n_faces;
  for (int i = 0; i < steps; ++i) n *= factor;
  return n;
}

// Writes one case; returns its line of cases.txt.
std::string write_case(const Mesh& mesh, const std::string& dir, const std::string& scheme,
                       int steps) {
  std::string xyz;
  for (auto v : mesh.vertices()) xyz.append(reinterpret_cast<const char*>(mesh.point(v).data()), 24);
  std::string tri;
  for (auto f : mesh.faces()) {
    auto h = mesh.halfedge_handle(f);
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = static_cast<uint32_t>(mesh.to_vertex_handle(h).idx());
      tri.append(reinterpret_cast<const char*>(&v), 4);
      h = mesh.next_halfedge_handle(h);
    }
    if (h != mesh.halfedge_handle(f)) fail(scheme + " produced a face that is not a triangle");
  }
  const std::string stem = dir + "/" + scheme + "_" + std::to_string(steps);
  write_file(stem + ".f64", xyz);
  write_file(stem + ".faces.u32", tri);
  std::ostringstream line;
  line << scheme << ' ' << steps << ' ' << mesh.n_vertices() << ' ' << mesh.n_faces() << '\n';
  return line.str();
}

}  // namespace

void write_subdivision(const std::string& input_ply, const std::string& out_dir) {
  check_little_endian();
  const Input data = read_ply(input_ply);
  for (const auto& face : data.faces)
    if (face.size() != 3) return;
  const Mesh base = build_mesh(data);

  const std::string dir = out_dir + "/subdivision";
  make_dir(out_dir);
  make_dir(dir);
  std::string cases;
  for (int steps : kSteps) {
    if (faces_after(base.n_faces(), steps, 4) <= kMaxFaces) {
      Mesh mesh = base;
      OpenMesh::Subdivider::Uniform::LoopT<Mesh, double> loop;
      if (!loop(mesh, steps)) fail("LoopT failed");
      cases += write_case(mesh, dir, "loop", steps);
    }
  }
  for (int steps : kSteps) {
    if (faces_after(base.n_faces(), steps, 3) <= kMaxFaces) {
      Mesh mesh = base;
      OpenMesh::Subdivider::Uniform::Sqrt3T<Mesh, double> sqrt3;
      if (!sqrt3(mesh, steps)) fail("Sqrt3T failed");
      cases += write_case(mesh, dir, "sqrt3", steps);
    }
  }
  write_file(dir + "/cases.txt", cases);
}

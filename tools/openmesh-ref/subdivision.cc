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
#include "ref_io.h"

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

using ref_io::check_little_endian;
using ref_io::fail;
using ref_io::Input;
using ref_io::make_dir;
using ref_io::read_ply;
using ref_io::write_file;
Mesh build_mesh(const Input& data) { return ref_io::build_mesh<Mesh>(data); }

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

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
#include "ref_io.h"

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

using ref_io::check_little_endian;
using ref_io::fail;
using ref_io::Input;
using ref_io::make_dir;
using ref_io::read_ply;
using ref_io::write_file;
Mesh build_mesh(const Input& data) { return ref_io::build_mesh<Mesh>(data); }

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

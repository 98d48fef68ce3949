// Editing references: OpenMesh's TriMesh Euler operators on a fixture.
//
// Writes into OUTPUT_DIR/editing/:
//
//   ops.txt      a deterministic sequence of queries and edits, each naming its vertices
//                by label (input vertices keep their input index; a vertex made by a
//                split gets the next label, counting from the input's vertex count):
//                  flip A B OK            is_flip_ok of edge A-B (1/0), flipped if 1
//                  collapse A B OK        is_collapse_ok of halfedge A->B, collapsed if 1
//                  split_edge A B N       split(edge A-B) at its midpoint, new vertex N
//                  split_face A B C N     split(face A B C) at its centroid, new vertex N
//                  delete_face A B C      delete_face(face A B C), isolated vertices too
//                  add_face A B C OK      add_face(A, B, C) accepted (1) or refused (0)
//   faces.txt    after the sequence and garbage_collection(): the faces of the input
//                that are gone ("removed A B C") and the faces that are new ("added A B
//                C"), each as labels rotated to start at the smallest, sorted
//   queries.txt  on the final mesh: is_collapse_ok for every halfedge, in the order of
//                (from label, to label), and is_flip_ok for every edge, in the order of
//                (smaller label, larger label), as strings of 0/1, 100 per line
//
// The sequence has two parts. First 600 flips, splits and collapses that walk: a focus
// vertex moves to the vertex an edit keeps or makes, and jumps to a random live vertex
// every 40 steps, so edits pile up locally and create the low-valence,
// boundary-touching configurations the preconditions are about. Then 150 face
// deletions and additions: deleted faces re-added in random order, boundary ears
// filled, random triangles at a boundary edge tried (add_face's complex vertex,
// complex edge and re-linking cases). Choices come from SplitMix64 with a fixed seed
// and from OpenMesh's circulation order, so the
// output is a deterministic function of the input.

#include "editing.h"

// GCC (-O2 -Wall) warns "may be used uninitialized" where it inlines OpenMesh's
// PropertyT<Vec3d>::push_back (a default-constructed point, left uninitialised by
// design) into add_vertex here; the value is overwritten at once.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#pragma GCC diagnostic pop

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <sys/stat.h>
#include <vector>

namespace {

struct EditTraits : public OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};
typedef OpenMesh::TriMesh_ArrayKernelT<EditTraits> EMesh;

const int kSteps = 600;
const int kJumpEvery = 40;
const int kFaceSteps = 150;
const uint64_t kSeed = 0x0edd17ULL;

[[noreturn]] void edit_fail(const std::string& m) { throw std::runtime_error(m); }

struct SplitMix64 {
  uint64_t state;
  uint64_t next() {
    state += 0x9e3779b97f4a7c15ULL;
    uint64_t z = state;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  size_t below(size_t n) { return static_cast<size_t>(next() % n); }
};

// The binary little-endian double PLY layout beltrami-io writes (vertices x y z as
// doubles, faces as a uchar count and int indices).
EMesh read_fixture(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) edit_fail("cannot open " + path);
  std::string line;
  long nv = -1, nf = -1;
  while (std::getline(in, line)) {
    if (line.rfind("element vertex ", 0) == 0) nv = std::stol(line.substr(15));
    if (line.rfind("element face ", 0) == 0) nf = std::stol(line.substr(13));
    if (line == "format ascii 1.0" || line == "format binary_big_endian 1.0")
      edit_fail(path + ": not binary little-endian");
    if (line == "end_header") break;
  }
  if (nv < 0 || nf < 0) edit_fail(path + ": no vertex or face element");
  EMesh mesh;
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_halfedge_status();
  mesh.request_face_status();
  for (long v = 0; v < nv; ++v) {
    double xyz[3];
    if (!in.read(reinterpret_cast<char*>(xyz), sizeof xyz)) edit_fail(path + ": truncated");
    mesh.add_vertex(EMesh::Point(xyz[0], xyz[1], xyz[2]));
  }
  for (long f = 0; f < nf; ++f) {
    unsigned char k;
    int32_t idx[3];
    if (!in.read(reinterpret_cast<char*>(&k), 1) || k != 3 ||
        !in.read(reinterpret_cast<char*>(idx), sizeof idx))
      edit_fail(path + ": truncated or not a triangle");
    if (!mesh.add_face(mesh.vertex_handle(idx[0]), mesh.vertex_handle(idx[1]),
                       mesh.vertex_handle(idx[2]))
             .is_valid())
      edit_fail(path + ": OpenMesh rejected face " + std::to_string(f));
  }
  return mesh;
}

typedef std::array<int, 3> Tri;

Tri rotated(int a, int b, int c) {
  if (b < a && b < c) return {b, c, a};
  if (c < a && c < b) return {c, a, b};
  return {a, b, c};
}

std::vector<Tri> face_labels(const EMesh& mesh, const OpenMesh::VPropHandleT<int>& label) {
  std::vector<Tri> faces;
  for (auto f : mesh.faces()) {
    int l[3], i = 0;
    for (auto v : mesh.fv_range(f)) l[i++] = mesh.property(label, v);
    faces.push_back(rotated(l[0], l[1], l[2]));
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

std::string bits(std::vector<std::pair<std::pair<int, int>, bool>> answers) {
  std::sort(answers.begin(), answers.end());
  std::string out;
  for (size_t i = 0; i < answers.size(); ++i) {
    out += answers[i].second ? '1' : '0';
    if (i % 100 == 99 || i + 1 == answers.size()) out += '\n';
  }
  return out;
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) edit_fail("cannot write " + path);
}

}  // namespace

void write_editing_references(const std::string& input_ply, const std::string& out_dir) {
  EMesh mesh = read_fixture(input_ply);
  OpenMesh::VPropHandleT<int> label;
  mesh.add_property(label);
  for (auto v : mesh.vertices()) mesh.property(label, v) = v.idx();
  int next_label = static_cast<int>(mesh.n_vertices());
  std::vector<Tri> input_faces = face_labels(mesh, label);

  SplitMix64 rng{kSeed};
  auto random_vertex = [&]() {
    for (;;) {
      auto v = mesh.vertex_handle(static_cast<int>(rng.below(mesh.n_vertices())));
      if (!mesh.status(v).deleted() && !mesh.is_isolated(v)) return v;
    }
  };
  auto lab = [&](OpenMesh::VertexHandle v) { return mesh.property(label, v); };

  std::ostringstream ops;
  EMesh::VertexHandle focus = random_vertex();
  for (int step = 0; step < kSteps; ++step) {
    if (step % kJumpEvery == 0 || mesh.status(focus).deleted() || mesh.is_isolated(focus))
      focus = random_vertex();
    std::vector<EMesh::HalfedgeHandle> out;
    for (auto h : mesh.voh_range(focus)) out.push_back(h);
    EMesh::HalfedgeHandle h = out[rng.below(out.size())];
    EMesh::VertexHandle a = mesh.from_vertex_handle(h), b = mesh.to_vertex_handle(h);
    uint64_t kind = rng.below(20);
    if (kind < 8) {
      if (rng.below(2)) {
        h = mesh.opposite_halfedge_handle(h);
        std::swap(a, b);
      }
      bool ok = mesh.is_collapse_ok(h);
      ops << "collapse " << lab(a) << ' ' << lab(b) << ' ' << ok << '\n';
      if (ok) mesh.collapse(h);
      focus = b;
    } else if (kind < 14) {
      auto e = mesh.edge_handle(h);
      bool ok = mesh.is_flip_ok(e);
      ops << "flip " << lab(a) << ' ' << lab(b) << ' ' << ok << '\n';
      if (ok) mesh.flip(e);
      focus = b;
    } else if (kind < 17) {
      auto vh = mesh.add_vertex((mesh.point(a) + mesh.point(b)) * 0.5);
      mesh.property(label, vh) = next_label;
      ops << "split_edge " << lab(a) << ' ' << lab(b) << ' ' << next_label << '\n';
      ++next_label;
      mesh.split(mesh.edge_handle(h), vh);
      focus = vh;
    } else {
      if (mesh.is_boundary(h)) h = mesh.opposite_halfedge_handle(h);
      auto f = mesh.face_handle(h);
      int l[3], i = 0;
      EMesh::Point c(0, 0, 0);
      for (auto v : mesh.fv_range(f)) {
        l[i++] = lab(v);
        c += mesh.point(v);
      }
      auto vh = mesh.add_vertex(c / 3.0);
      mesh.property(label, vh) = next_label;
      ops << "split_face " << l[0] << ' ' << l[1] << ' ' << l[2] << ' ' << next_label << '\n';
      ++next_label;
      mesh.split(f, vh);
      focus = vh;
    }
  }

  // Deleting and adding faces: delete faces, re-add deleted ones in random order, and
  // fill boundary ears (a boundary halfedge, its successor, and either the vertex that
  // closes the ear or a random neighbour), with OpenMesh's accept/refuse answer.
  omerr().disable();
  std::vector<std::array<EMesh::VertexHandle, 3>> pool;
  for (int step = 0; step < kFaceSteps; ++step) {
    uint64_t kind = rng.below(10);
    if (kind < 4) {
      EMesh::FaceHandle f;
      do f = mesh.face_handle(static_cast<int>(rng.below(mesh.n_faces())));
      while (mesh.status(f).deleted());
      std::array<EMesh::VertexHandle, 3> t;
      int i = 0;
      for (auto v : mesh.fv_range(f)) t[i++] = v;
      pool.push_back(t);
      ops << "delete_face " << lab(t[0]) << ' ' << lab(t[1]) << ' ' << lab(t[2]) << '\n';
      mesh.delete_face(f, true);
      continue;
    }
    std::array<EMesh::VertexHandle, 3> t;
    if (kind < 7) {
      if (pool.empty()) continue;
      size_t k = rng.below(pool.size());
      t = pool[k];
      pool.erase(pool.begin() + static_cast<long>(k));
    } else {
      EMesh::HalfedgeHandle h;
      size_t tries = 0;
      do h = mesh.halfedge_handle(static_cast<int>(rng.below(mesh.n_halfedges())));
      while ((mesh.status(mesh.edge_handle(h)).deleted() || !mesh.is_boundary(h)) &&
             ++tries < 100000);
      if (tries == 100000) continue;
      EMesh::VertexHandle a = mesh.from_vertex_handle(h), b = mesh.to_vertex_handle(h);
      EMesh::VertexHandle c = mesh.to_vertex_handle(mesh.next_halfedge_handle(h));
      if (kind == 9) {
        std::vector<EMesh::VertexHandle> ring;
        for (auto v : mesh.vv_range(b)) ring.push_back(v);
        c = ring[rng.below(ring.size())];
      }
      t = {a, b, c};
    }
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
    if (mesh.status(t[0]).deleted() || mesh.status(t[1]).deleted() || mesh.status(t[2]).deleted())
      continue;
    bool ok = mesh.add_face(t[0], t[1], t[2]).is_valid();
    ops << "add_face " << lab(t[0]) << ' ' << lab(t[1]) << ' ' << lab(t[2]) << ' ' << ok << '\n';
  }
  mesh.garbage_collection();

  std::vector<Tri> final_faces = face_labels(mesh, label);
  std::vector<Tri> removed, added;
  std::set_difference(input_faces.begin(), input_faces.end(), final_faces.begin(),
                      final_faces.end(), std::back_inserter(removed));
  std::set_difference(final_faces.begin(), final_faces.end(), input_faces.begin(),
                      input_faces.end(), std::back_inserter(added));
  std::ostringstream faces;
  for (const Tri& t : removed) faces << "removed " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
  for (const Tri& t : added) faces << "added " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';

  std::vector<std::pair<std::pair<int, int>, bool>> collapse_ok, flip_ok;
  for (auto h : mesh.halfedges())
    collapse_ok.push_back({{lab(mesh.from_vertex_handle(h)), lab(mesh.to_vertex_handle(h))},
                           mesh.is_collapse_ok(h)});
  for (auto e : mesh.edges()) {
    int x = lab(mesh.to_vertex_handle(mesh.halfedge_handle(e, 0)));
    int y = lab(mesh.to_vertex_handle(mesh.halfedge_handle(e, 1)));
    flip_ok.push_back({{std::min(x, y), std::max(x, y)}, mesh.is_flip_ok(e)});
  }

  std::string dir = out_dir + "/editing";
  for (const std::string& d : {out_dir, dir})
    if (mkdir(d.c_str(), 0755) != 0 && errno != EEXIST) edit_fail("cannot create " + d);
  write_text(dir + "/ops.txt", ops.str());
  write_text(dir + "/faces.txt", faces.str());
  write_text(dir + "/queries.txt", "# collapse_ok\n" + bits(collapse_ok) + "# flip_ok\n" + bits(flip_ok));
}

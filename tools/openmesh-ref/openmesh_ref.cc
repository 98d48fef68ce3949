// openmesh-ref: reference results for beltrami, computed with OpenMesh.
//
//   openmesh-ref INPUT.ply OUTPUT_DIR NAME [--max-iterations N]
//
// --max-iterations N leaves out the cases with more than N iterations (of both the
// smoother and the paper's experiment); fixtures.txt uses it to keep a large fixture's
// references small.
//
// Reads a mesh from a binary little-endian PLY with double coordinates (the layout
// beltrami-io writes), builds an OpenMesh TriMesh from the exact doubles with
// add_vertex/add_face (OpenMesh's own PLY reader passes coordinates through float),
// and writes into OUTPUT_DIR:
//
//   summary.json            counts, boundary loops, bounding box, area, volume, case list
//   topology.txt            per-vertex valence, boundary flag, outgoing halfedge and
//                           one-ring; per-edge end points; per-face halfedge and vertices
//   face_normals.f64        update_normals(): 3 doubles per face
//   vertex_normals.f64      update_normals(): 3 doubles per vertex
//   face_areas.f64          calc_sector_area(halfedge_handle(f)): 1 double per face
//   openmesh_smoother/*     JacobiLaplaceSmootherT, C0, 1/10/100 iterations
//   paper/*                 the paper's explicit smoothing (lambda = 0.8), written here
//                           on OpenMesh's connectivity and circulation
//
// *.f64 files are raw little-endian IEEE-754 doubles without a header. Positions are
// binary little-endian double PLY files with the vertices only (the faces are those of
// the input). Every output is a deterministic function of the input: no times, no
// addresses, doubles printed with 17 significant digits.
//
// Arithmetic of the paper's experiment (so that a reader can check it operation by
// operation; it is the order docs/laplacian.md documents for beltrami):
//   ring of v: halfedge_handle(v), then ccw_rotated_halfedge_handle until back;
//   W = sum of the ring's weights in ring order, scale = 1 / W, the vertex is stuck
//       (does not move) unless scale is positive and finite;
//   s = sum of p_j * w_ij in ring order, starting from zero;
//   p_new = p + (s * scale - p) * lambda, every vertex from the previous iterate.
//   uniform   w = 1
//   distance  w = 1 / (|p_j - p_i| + 1e-12), |d| = sqrt((dx dx + dy dy) + dz dz)
//   cotangent w = 0.5 * (cot(h0) + cot(h1)) for the edge's halfedges h0 = 2e, h1 = 2e + 1;
//             cot(h) = (u . v) / |u x v| at the corner opposite h, u and v the edges
//             from that corner to to_vertex(h) and from_vertex(h); 0 for a boundary
//             halfedge, when |u x v| = 0 or the quotient is not finite, and for a
//             degenerate face: |s1 x s2| <= 1e-12 * max(|s1|^2, |s2|^2, |s2 - s1|^2)
//             with p0, p1, p2 the face's vertices from halfedge_handle(f) and
//             s1 = p1 - p0, s2 = p2 - p0. Negative weights are kept.
//   Weights every iteration (from the current positions) or once (from the input).
//   Boundary fixed (boundary vertices never move) or free (smoothed over their
//   one-sided ring). Isolated vertices never move.

#include "decimation.h"
#include "editing.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Smoother/JacobiLaplaceSmootherT.hh>

#include "subdivision.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <limits>
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
typedef OpenMesh::Smoother::JacobiLaplaceSmootherT<Mesh> Smoother;
typedef OpenMesh::Vec3d Vec;

const int kSmootherIterations[] = {1, 10, 100};
const int kPaperIterations[] = {10, 100};
const double kPaperLambda = 0.8;
const double kDistanceEpsilon = 1e-12;
const double kDegeneracyRatio = 1e-12;

[[noreturn]] void fail(const std::string& message) { throw std::runtime_error(message); }

// ---------------------------------------------------------------- input

struct Input {
  std::vector<Vec> positions;
  std::vector<std::vector<int>> faces;
};

// Reads the binary little-endian double PLY layout beltrami-io writes:
// `element vertex N` with `property double x|y|z` (exactly these three, in this order),
// then `element face F` with `property list uchar int vertex_indices`. Comments are
// skipped; anything else is an error, so that no coordinate is ever converted.
Input read_ply(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("cannot open " + path);
  std::string line;
  std::getline(in, line);
  if (line != "ply") fail(path + ": not a PLY file");
  std::vector<std::string> header;
  while (std::getline(in, line)) {
    if (line.rfind("comment", 0) == 0 || line.rfind("obj_info", 0) == 0) continue;
    header.push_back(line);
    if (line == "end_header") break;
  }
  long n_vertices = -1, n_faces = -1;
  size_t i = 0;
  auto expect = [&](const std::string& want) {
    if (i >= header.size() || header[i] != want)
      fail(path + ": expected header line '" + want + "', found '" +
           (i < header.size() ? header[i] : std::string("<end>")) + "'");
    ++i;
  };
  auto count = [&](const std::string& prefix) {
    if (i >= header.size() || header[i].rfind(prefix, 0) != 0)
      fail(path + ": expected '" + prefix + "N'");
    long n = std::stol(header[i].substr(prefix.size()));
    ++i;
    return n;
  };
  expect("format binary_little_endian 1.0");
  n_vertices = count("element vertex ");
  expect("property double x");
  expect("property double y");
  expect("property double z");
  n_faces = count("element face ");
  if (i < header.size() && header[i] == "property list uint8 int32 vertex_indices") {
    ++i;
  } else {
    expect("property list uchar int vertex_indices");
  }
  expect("end_header");
  if (n_vertices < 0 || n_faces < 0) fail(path + ": negative element count");

  Input data;
  data.positions.resize(n_vertices);
  for (long v = 0; v < n_vertices; ++v) {
    double xyz[3];
    if (!in.read(reinterpret_cast<char*>(xyz), sizeof xyz)) fail(path + ": truncated vertices");
    data.positions[v] = Vec(xyz[0], xyz[1], xyz[2]);
  }
  data.faces.resize(n_faces);
  for (long f = 0; f < n_faces; ++f) {
    unsigned char k;
    if (!in.read(reinterpret_cast<char*>(&k), 1)) fail(path + ": truncated faces");
    std::vector<int32_t> idx(k);
    if (!in.read(reinterpret_cast<char*>(idx.data()), 4 * k)) fail(path + ": truncated faces");
    for (int32_t j : idx)
      if (j < 0 || j >= n_vertices) fail(path + ": face index out of range");
    data.faces[f].assign(idx.begin(), idx.end());
  }
  char extra;
  if (in.read(&extra, 1)) fail(path + ": trailing bytes after the faces");
  return data;
}

Mesh build_mesh(const Input& data) {
  Mesh mesh;
  std::vector<Mesh::VertexHandle> vh;
  vh.reserve(data.positions.size());
  for (const Vec& p : data.positions) vh.push_back(mesh.add_vertex(p));
  for (size_t f = 0; f < data.faces.size(); ++f) {
    if (data.faces[f].size() != 3) fail("face " + std::to_string(f) + " is not a triangle");
    std::vector<Mesh::VertexHandle> face;
    for (int i : data.faces[f]) face.push_back(vh[i]);
    if (!mesh.add_face(face).is_valid()) fail("OpenMesh rejected face " + std::to_string(f));
  }
  if (mesh.n_faces() != data.faces.size()) fail("face count changed");
  return mesh;
}

// ---------------------------------------------------------------- output helpers

std::string num(double x) {
  if (!std::isfinite(x)) fail("non-finite value in an output");
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

void make_dir(const std::string& path) {
  if (mkdir(path.c_str(), 0755) != 0 && errno != EEXIST) fail("cannot create " + path);
}

void write_file(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) fail("cannot write " + path);
}

void append_doubles(std::string& bytes, const double* x, size_t n) {
  static_assert(sizeof(double) == 8, "IEEE-754 double");
  const uint16_t probe = 1;
  if (*reinterpret_cast<const unsigned char*>(&probe) != 1) fail("big-endian host");
  bytes.append(reinterpret_cast<const char*>(x), 8 * n);
}

// Positions only: a binary little-endian double PLY with an empty face element.
void write_positions(const std::string& path, const std::vector<Vec>& positions,
                     const std::string& comment) {
  std::ostringstream header;
  header << "ply\nformat binary_little_endian 1.0\ncomment " << comment
         << "\ncomment faces: those of the input mesh\nelement vertex " << positions.size()
         << "\nproperty double x\nproperty double y\nproperty double z\nelement face 0\n"
            "property list uchar int vertex_indices\nend_header\n";
  std::string bytes = header.str();
  for (const Vec& p : positions) append_doubles(bytes, p.data(), 3);
  write_file(path, bytes);
}

std::vector<Vec> points_of(const Mesh& mesh) {
  std::vector<Vec> out;
  out.reserve(mesh.n_vertices());
  for (auto v : mesh.vertices()) out.push_back(mesh.point(v));
  return out;
}

// ---------------------------------------------------------------- plain arithmetic
// Written out component by component so that the order of every operation is the one
// documented at the top of this file.

double dot3(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

Vec cross3(const Vec& a, const Vec& b) {
  return Vec(a[1] * b[2] - b[1] * a[2], a[2] * b[0] - b[2] * a[0], a[0] * b[1] - b[0] * a[1]);
}

double length3(const Vec& a) { return std::sqrt(dot3(a, a)); }

// Neumaier's compensated sum.
struct Sum {
  double sum = 0.0, c = 0.0;
  void add(double x) {
    double t = sum + x;
    if (std::fabs(sum) >= std::fabs(x))
      c += (sum - t) + x;
    else
      c += (x - t) + sum;
    sum = t;
  }
  double value() const { return sum + c; }
};

struct Displacement {
  double max = 0.0, rms = 0.0;
  int moved = 0;
};

Displacement displacement(const std::vector<Vec>& from, const std::vector<Vec>& to) {
  Displacement d;
  Sum squares;
  for (size_t i = 0; i < from.size(); ++i) {
    Vec delta = to[i] - from[i];
    double l = length3(delta);
    d.max = std::max(d.max, l);
    squares.add(l * l);
    if (to[i] != from[i]) ++d.moved;
  }
  d.rms = from.empty() ? 0.0 : std::sqrt(squares.value() / static_cast<double>(from.size()));
  return d;
}

// ---------------------------------------------------------------- topology and geometry

struct Loop {
  int first_halfedge;
  int length;
};

std::vector<Loop> boundary_loops(const Mesh& mesh) {
  std::vector<Loop> loops;
  std::vector<char> seen(mesh.n_halfedges(), 0);
  for (auto h : mesh.halfedges()) {
    if (!mesh.is_boundary(h) || seen[h.idx()]) continue;
    Loop loop{h.idx(), 0};
    Mesh::HalfedgeHandle g = h;
    do {
      seen[g.idx()] = 1;
      ++loop.length;
      g = mesh.next_halfedge_handle(g);
    } while (g != h);
    loops.push_back(loop);
  }
  return loops;
}

std::string topology_text(const Mesh& mesh) {
  std::ostringstream out;
  out << "# openmesh-ref topology: OpenMesh's view of the input mesh\n"
         "# v <vertex> <valence> <boundary 0|1> <halfedge_handle(v) or -1> : <one-ring, "
         "counter-clockwise from the target of halfedge_handle(v)>\n"
         "# e <edge> <from_vertex(2e)> <to_vertex(2e)>\n"
         "# f <face> <halfedge_handle(f)> : <vertices from the target of halfedge_handle(f)>\n"
         "# l <first (lowest) halfedge of a boundary loop> <length>\n";
  for (auto v : mesh.vertices()) {
    auto h0 = mesh.halfedge_handle(v);
    out << "v " << v.idx() << ' ' << mesh.valence(v) << ' ' << (mesh.is_boundary(v) ? 1 : 0)
        << ' ' << (h0.is_valid() ? h0.idx() : -1) << " :";
    if (h0.is_valid()) {
      auto h = h0;
      do {
        out << ' ' << mesh.to_vertex_handle(h).idx();
        h = mesh.ccw_rotated_halfedge_handle(h);
      } while (h != h0);
    }
    out << '\n';
  }
  for (auto e : mesh.edges()) {
    auto h = mesh.halfedge_handle(e, 0);
    out << "e " << e.idx() << ' ' << mesh.from_vertex_handle(h).idx() << ' '
        << mesh.to_vertex_handle(h).idx() << '\n';
  }
  for (auto f : mesh.faces()) {
    auto h0 = mesh.halfedge_handle(f);
    out << "f " << f.idx() << ' ' << h0.idx() << " :";
    auto h = h0;
    do {
      out << ' ' << mesh.to_vertex_handle(h).idx();
      h = mesh.next_halfedge_handle(h);
    } while (h != h0);
    out << '\n';
  }
  for (const Loop& l : boundary_loops(mesh)) out << "l " << l.first_halfedge << ' ' << l.length << '\n';
  return out.str();
}

// Enclosed volume of a closed triangle mesh: sum of p0 . (p1 x p2) / 6 with the points
// taken relative to the centre of the bounding box, compensated.
double volume(const Mesh& mesh, const Vec& centre) {
  Sum sum;
  for (auto f : mesh.faces()) {
    auto h = mesh.halfedge_handle(f);
    Vec p0 = mesh.point(mesh.to_vertex_handle(h)) - centre;
    h = mesh.next_halfedge_handle(h);
    Vec p1 = mesh.point(mesh.to_vertex_handle(h)) - centre;
    h = mesh.next_halfedge_handle(h);
    Vec p2 = mesh.point(mesh.to_vertex_handle(h)) - centre;
    sum.add(dot3(p0, cross3(p1, p2)));
  }
  return sum.value() / 6.0;
}

// ---------------------------------------------------------------- the paper's experiment

enum class Scheme { Uniform, Distance, Cotangent };
enum class Update { Every, Once };
enum class BoundaryMode { Fixed, Free };

const char* scheme_name(Scheme s) {
  switch (s) {
    case Scheme::Uniform: return "uniform";
    case Scheme::Distance: return "distance";
    case Scheme::Cotangent: return "cotangent";
  }
  return "";
}

// cot of the corner opposite halfedge h (see the top of the file).
double opposite_cot(const Mesh& mesh, const std::vector<Vec>& p, Mesh::HalfedgeHandle h) {
  if (mesh.is_boundary(h)) return 0.0;
  auto f = mesh.face_handle(h);
  auto fh = mesh.halfedge_handle(f);
  const Vec& q0 = p[mesh.to_vertex_handle(fh).idx()];
  fh = mesh.next_halfedge_handle(fh);
  const Vec& q1 = p[mesh.to_vertex_handle(fh).idx()];
  fh = mesh.next_halfedge_handle(fh);
  const Vec& q2 = p[mesh.to_vertex_handle(fh).idx()];
  Vec s1 = q1 - q0, s2 = q2 - q0, s3 = s2 - s1;
  double longest2 = std::max(std::max(dot3(s1, s1), dot3(s2, s2)), dot3(s3, s3));
  double two_area = length3(cross3(s1, s2));
  if (two_area <= kDegeneracyRatio * longest2 || std::isnan(two_area)) return 0.0;

  const Vec& c = p[mesh.to_vertex_handle(mesh.next_halfedge_handle(h)).idx()];
  Vec u = p[mesh.to_vertex_handle(h).idx()] - c;
  Vec v = p[mesh.from_vertex_handle(h).idx()] - c;
  double cross = length3(cross3(u, v));
  if (!(cross > 0.0)) return 0.0;
  double cot = dot3(u, v) / cross;
  return std::isfinite(cot) ? cot : 0.0;
}

void fill_weights(const Mesh& mesh, const std::vector<Vec>& p, Scheme scheme,
                  std::vector<double>& w) {
  w.assign(mesh.n_halfedges(), 0.0);
  switch (scheme) {
    case Scheme::Uniform:
      std::fill(w.begin(), w.end(), 1.0);
      break;
    case Scheme::Distance:
      for (auto h : mesh.halfedges()) {
        Vec d = p[mesh.to_vertex_handle(h).idx()] - p[mesh.from_vertex_handle(h).idx()];
        w[h.idx()] = 1.0 / (length3(d) + kDistanceEpsilon);
      }
      break;
    case Scheme::Cotangent:
      for (auto e : mesh.edges()) {
        auto h0 = mesh.halfedge_handle(e, 0), h1 = mesh.halfedge_handle(e, 1);
        double we = 0.5 * (opposite_cot(mesh, p, h0) + opposite_cot(mesh, p, h1));
        w[h0.idx()] = we;
        w[h1.idx()] = we;
      }
      break;
  }
}

struct PaperResult {
  std::vector<Vec> positions;
  int max_stuck = 0;
  int negative_weights = 0;  // halfedges with w < 0 in the first weights
  int smoothed_vertices = 0;
};

// Runs the explicit smoothing and records the positions after each iteration count in
// `checkpoints` (ascending).
std::vector<PaperResult> run_paper(const Mesh& mesh, const std::vector<Vec>& input, Scheme scheme,
                                   Update update, BoundaryMode boundary,
                                   const std::vector<int>& checkpoints) {
  const size_t n = mesh.n_vertices();
  std::vector<char> moves(n, 0);
  int smoothed = 0;
  for (auto v : mesh.vertices()) {
    bool isolated = !mesh.halfedge_handle(v).is_valid();
    bool still = isolated || (boundary == BoundaryMode::Fixed && mesh.is_boundary(v));
    moves[v.idx()] = still ? 0 : 1;
    smoothed += still ? 0 : 1;
  }
  std::vector<Vec> p = input, next = input;
  std::vector<double> w;
  fill_weights(mesh, p, scheme, w);
  int negative = 0;
  for (double x : w) negative += x < 0.0 ? 1 : 0;

  std::vector<PaperResult> results;
  int max_stuck = 0;
  size_t k = 0;
  for (int it = 1; k < checkpoints.size(); ++it) {
    if (update == Update::Every && it > 1) fill_weights(mesh, p, scheme, w);
    int stuck = 0;
    for (auto v : mesh.vertices()) {
      const Vec xi = p[v.idx()];
      next[v.idx()] = xi;
      if (!moves[v.idx()]) continue;
      auto h0 = mesh.halfedge_handle(v);
      double weight_sum = -0.0;
      auto h = h0;
      do {
        weight_sum += w[h.idx()];
        h = mesh.ccw_rotated_halfedge_handle(h);
      } while (h != h0);
      double scale = 1.0 / weight_sum;
      if (!(std::isfinite(scale) && scale > 0.0)) {
        ++stuck;
        continue;
      }
      Vec s(0.0, 0.0, 0.0);
      h = h0;
      do {
        const Vec& xj = p[mesh.to_vertex_handle(h).idx()];
        const double wj = w[h.idx()];
        s = Vec(s[0] + xj[0] * wj, s[1] + xj[1] * wj, s[2] + xj[2] * wj);
        h = mesh.ccw_rotated_halfedge_handle(h);
      } while (h != h0);
      Vec l(s[0] * scale - xi[0], s[1] * scale - xi[1], s[2] * scale - xi[2]);
      next[v.idx()] = Vec(xi[0] + l[0] * kPaperLambda, xi[1] + l[1] * kPaperLambda,
                          xi[2] + l[2] * kPaperLambda);
    }
    max_stuck = std::max(max_stuck, stuck);
    std::swap(p, next);
    if (it == checkpoints[k]) {
      results.push_back(PaperResult{p, max_stuck, negative, smoothed});
      ++k;
    }
  }
  return results;
}

// ---------------------------------------------------------------- driver

struct CaseEntry {
  std::string kind, name;
};

std::string case_json(const std::string& kind, const std::string& name, const std::string& params,
                      int iterations, const std::string& file, const std::vector<Vec>& input,
                      const std::vector<Vec>& output, const std::string& extra) {
  Displacement d = displacement(input, output);
  std::ostringstream j;
  j << "{\n  \"kind\": \"" << kind << "\",\n  \"case\": \"" << name << "\",\n" << params
    << "  \"iterations\": " << iterations << ",\n  \"positions\": \"" << file << "\",\n"
    << extra << "  \"moved_vertices\": " << d.moved
    << ",\n  \"max_displacement\": " << num(d.max) << ",\n  \"rms_displacement\": " << num(d.rms)
    << "\n}\n";
  return j.str();
}

int run(const std::string& input_path, const std::string& out_dir, const std::string& name,
        int max_iterations) {
  // The paper's iteration counts that are written (checked before anything is).
  std::vector<int> checkpoints;
  for (int n : kPaperIterations)
    if (n <= max_iterations) checkpoints.push_back(n);
  if (checkpoints.empty()) fail("--max-iterations leaves no case of the paper's experiment");

  const Input data = read_ply(input_path);
  Mesh base = build_mesh(data);
  const std::vector<Vec> input = points_of(base);
  const bool closed = boundary_loops(base).empty();

  make_dir(out_dir);
  make_dir(out_dir + "/openmesh_smoother");
  make_dir(out_dir + "/paper");

  // Topology.
  write_file(out_dir + "/topology.txt", topology_text(base));

  // Geometry.
  {
    Mesh mesh = base;
    mesh.request_face_normals();
    mesh.request_vertex_normals();
    mesh.update_normals();
    std::string fn, vn, fa;
    for (auto f : mesh.faces()) {
      append_doubles(fn, mesh.normal(f).data(), 3);
      double a = mesh.calc_sector_area(mesh.halfedge_handle(f));
      append_doubles(fa, &a, 1);
    }
    for (auto v : mesh.vertices()) append_doubles(vn, mesh.normal(v).data(), 3);
    write_file(out_dir + "/face_normals.f64", fn);
    write_file(out_dir + "/vertex_normals.f64", vn);
    write_file(out_dir + "/face_areas.f64", fa);
  }

  std::vector<CaseEntry> cases;

  // OpenMesh's own smoother.
  struct Component {
    const char* name;
    Smoother::Component component;
    const char* weights;
  };
  const Component components[] = {
      {"tangential_and_normal", Smoother::Tangential_and_Normal, "uniform"},
      {"normal", Smoother::Normal, "cotangent (1/tan(acos(dot)))"},
  };
  for (const Component& c : components) {
    for (int n : kSmootherIterations) {
      if (n > max_iterations) continue;
      Mesh mesh = base;
      Smoother smoother(mesh);
      smoother.initialize(c.component, Smoother::C0);
      smoother.smooth(static_cast<unsigned int>(n));
      std::vector<Vec> out = points_of(mesh);
      std::string case_name = std::string(c.name) + "_c0_" + std::to_string(n);
      std::string file = case_name + ".ply";
      write_positions(out_dir + "/openmesh_smoother/" + file, out,
                      "OpenMesh JacobiLaplaceSmootherT " + std::string(c.name) + " C0, " +
                          std::to_string(n) + " iterations, input " + name);
      std::ostringstream params;
      params << "  \"component\": \"" << c.name << "\",\n  \"continuity\": \"C0\",\n"
             << "  \"weights\": \"" << c.weights << "\",\n  \"lambda\": 0.5,\n"
             << "  \"update\": \"once\",\n  \"boundary\": \"fixed\",\n";
      write_file(out_dir + "/openmesh_smoother/" + case_name + ".json",
                 case_json("openmesh_smoother", case_name, params.str(), n, file, input, out, ""));
      cases.push_back({"openmesh_smoother", case_name});
    }
  }

  // The paper's experiment.
  for (Scheme scheme : {Scheme::Uniform, Scheme::Distance, Scheme::Cotangent}) {
    for (Update update : {Update::Every, Update::Once}) {
      for (BoundaryMode boundary : {BoundaryMode::Fixed, BoundaryMode::Free}) {
        // A closed mesh has no boundary: the free-boundary run equals the fixed one and
        // is not written twice.
        if (closed && boundary == BoundaryMode::Free) continue;
        std::vector<PaperResult> results = run_paper(base, input, scheme, update, boundary, checkpoints);
        for (size_t k = 0; k < checkpoints.size(); ++k) {
          const PaperResult& r = results[k];
          std::string case_name = std::string(scheme_name(scheme)) + "_" +
                                  (update == Update::Every ? "every" : "once") + "_" +
                                  (boundary == BoundaryMode::Fixed ? "fixed" : "free") + "_" +
                                  std::to_string(checkpoints[k]);
          std::string file = case_name + ".ply";
          write_positions(out_dir + "/paper/" + file, r.positions,
                          "explicit smoothing " + case_name + ", lambda 0.8, input " + name);
          std::ostringstream params;
          params << "  \"scheme\": \"" << scheme_name(scheme) << "\",\n  \"lambda\": 0.8,\n"
                 << "  \"update\": \"" << (update == Update::Every ? "every" : "once")
                 << "\",\n  \"boundary\": \""
                 << (boundary == BoundaryMode::Fixed ? "fixed" : "free") << "\",\n"
                 << "  \"negative_weights\": \"keep\",\n";
          std::ostringstream extra;
          extra << "  \"smoothed_vertices\": " << r.smoothed_vertices
                << ",\n  \"negative_halfedge_weights_first_iteration\": " << r.negative_weights
                << ",\n  \"max_stuck_vertices\": " << r.max_stuck << ",\n";
          write_file(out_dir + "/paper/" + case_name + ".json",
                     case_json("paper", case_name, params.str(), checkpoints[k], file, input,
                               r.positions, extra.str()));
          cases.push_back({"paper", case_name});
        }
      }
    }
  }

  // Summary.
  Vec lo = input.empty() ? Vec(0, 0, 0) : input[0], hi = lo;
  for (const Vec& p : input) {
    lo.minimize(p);
    hi.maximize(p);
  }
  Vec centre = (lo + hi) * 0.5;
  Sum area;
  for (auto f : base.faces()) area.add(base.calc_sector_area(base.halfedge_handle(f)));
  int boundary_halfedges = 0, boundary_vertices = 0;
  for (auto h : base.halfedges()) boundary_halfedges += base.is_boundary(h) ? 1 : 0;
  for (auto v : base.vertices()) boundary_vertices += base.is_boundary(v) ? 1 : 0;
  std::vector<Loop> loops = boundary_loops(base);

  std::ostringstream s;
  s << "{\n  \"fixture\": \"" << name << "\",\n  \"input\": \"" << input_path << "\",\n"
    << "  \"openmesh\": \"" << OM_GET_VER << '.' << OM_GET_MAJ << '.' << OM_GET_MIN << "\",\n"
    << "  \"vertices\": " << base.n_vertices() << ",\n  \"edges\": " << base.n_edges()
    << ",\n  \"faces\": " << base.n_faces() << ",\n  \"halfedges\": " << base.n_halfedges()
    << ",\n  \"boundary_halfedges\": " << boundary_halfedges
    << ",\n  \"boundary_vertices\": " << boundary_vertices << ",\n  \"boundary_loops\": [";
  for (size_t i = 0; i < loops.size(); ++i) s << (i ? ", " : "") << loops[i].length;
  s << "],\n  \"closed\": " << (closed ? "true" : "false") << ",\n  \"bbox_min\": [" << num(lo[0])
    << ", " << num(lo[1]) << ", " << num(lo[2]) << "],\n  \"bbox_max\": [" << num(hi[0]) << ", "
    << num(hi[1]) << ", " << num(hi[2]) << "],\n  \"bbox_diagonal\": " << num(length3(hi - lo))
    << ",\n  \"surface_area\": " << num(area.value()) << ",\n  \"volume\": "
    << (closed ? num(volume(base, centre)) : std::string("null")) << ",\n  \"cases\": [\n";
  for (size_t i = 0; i < cases.size(); ++i)
    s << "    \"" << cases[i].kind << '/' << cases[i].name << '"' << (i + 1 < cases.size() ? ",\n" : "\n");
  s << "  ]\n}\n";
  write_file(out_dir + "/summary.json", s.str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  int max_iterations = std::numeric_limits<int>::max();
  bool usage = argc != 4 && argc != 6;
  if (argc == 6) {
    char* end = nullptr;
    long n = std::strtol(argv[5], &end, 10);
    usage = std::strcmp(argv[4], "--max-iterations") != 0 || *argv[5] == '\0' || *end != '\0' ||
            n < 1 || n > std::numeric_limits<int>::max();
    max_iterations = static_cast<int>(n);
  }
  if (usage) {
    std::fprintf(stderr, "usage: %s INPUT.ply OUTPUT_DIR NAME [--max-iterations N]\n", argv[0]);
    return 2;
  }
  try {
    write_editing_references(argv[1], argv[2]);
    write_subdivision(argv[1], argv[2]);
    write_decimation(argv[1], argv[2]);
    return run(argv[1], argv[2], argv[3], max_iterations);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "openmesh-ref: %s\n", e.what());
    return 1;
  }
}

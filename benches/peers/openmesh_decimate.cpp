// OpenMesh's quadric decimation, timed.
//
//   openmesh_decimate MESH.ply OUT.ply RATIO REPS
//
// OpenMesh::Decimater::DecimaterT with ModQuadricT (priority mode, no error bound) on a
// double-precision TriMesh, down to round(RATIO * vertices) vertices. Each repetition
// copies the input, builds the decimater and decimates; only the initialisation and the
// decimation are timed (not reading, not the copy, not the garbage collection and the
// write of the last repetition's result to OUT). Prints one JSON object: the vertex and
// face counts of the result and the wall time of every repetition, in seconds.
// Build: g++ -O2 -DNDEBUG -std=c++17 openmesh_decimate.cpp -lOpenMeshCore -lOpenMeshTools
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

struct DoubleTraits : public OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};
using Mesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

static double wall() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: openmesh_decimate MESH.ply OUT.ply RATIO REPS\n");
    return 2;
  }
  const double ratio = std::atof(argv[3]);
  const int reps = std::atoi(argv[4]);
  Mesh input;
  if (!OpenMesh::IO::read_mesh(input, argv[1])) {
    std::fprintf(stderr, "error: OpenMesh cannot read %s\n", argv[1]);
    return 1;
  }
  input.request_vertex_status();
  input.request_edge_status();
  input.request_face_status();
  input.request_face_normals();
  input.update_face_normals();
  const size_t target = size_t(std::llround(ratio * double(input.n_vertices())));
  std::vector<double> seconds;
  Mesh mesh;
  for (int r = 0; r < reps; ++r) {
    mesh = input;
    const double t0 = wall();
    OpenMesh::Decimater::DecimaterT<Mesh> decimater(mesh);
    OpenMesh::Decimater::ModQuadricT<Mesh>::Handle quadric;
    decimater.add(quadric);
    decimater.module(quadric).unset_max_err();
    decimater.initialize();
    decimater.decimate_to(target);
    seconds.push_back(wall() - t0);
  }
  mesh.garbage_collection();
  if (!OpenMesh::IO::write_mesh(mesh, argv[2], OpenMesh::IO::Options::Binary)) {
    std::fprintf(stderr, "error: OpenMesh cannot write %s\n", argv[2]);
    return 1;
  }
  std::printf("{\"vertices\": %zu, \"faces\": %zu, \"seconds\": [", size_t(mesh.n_vertices()),
              size_t(mesh.n_faces()));
  for (size_t i = 0; i < seconds.size(); ++i) std::printf("%s%.6f", i ? ", " : "", seconds[i]);
  std::printf("]}\n");
  return 0;
}

// OpenMesh's uniform Loop subdivision, timed.
//
//   openmesh_subdivide MESH.ply STEPS REPS
//
// OpenMesh::Subdivider::Uniform::LoopT on a double-precision TriMesh: each repetition
// copies the input and subdivides the copy STEPS times in one call; only the call is
// timed (not reading, not the copy). Prints one JSON object: the vertex and face counts
// of the result and the wall time of every repetition, in seconds.
// Build: g++ -O2 -DNDEBUG -std=c++17 openmesh_subdivide.cpp -lOpenMeshCore -lOpenMeshTools
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>

#include <chrono>
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
  if (argc != 4) {
    std::fprintf(stderr, "usage: openmesh_subdivide MESH.ply STEPS REPS\n");
    return 2;
  }
  const int steps = std::atoi(argv[2]);
  const int reps = std::atoi(argv[3]);
  Mesh input;
  if (!OpenMesh::IO::read_mesh(input, argv[1])) {
    std::fprintf(stderr, "error: OpenMesh cannot read %s\n", argv[1]);
    return 1;
  }
  std::vector<double> seconds;
  Mesh mesh;
  for (int r = 0; r < reps; ++r) {
    mesh = input;
    OpenMesh::Subdivider::Uniform::LoopT<Mesh, double> loop;
    const double t0 = wall();
    if (!loop(mesh, steps)) {
      std::fprintf(stderr, "error: LoopT failed\n");
      return 1;
    }
    seconds.push_back(wall() - t0);
  }
  std::printf("{\"vertices\": %zu, \"faces\": %zu, \"seconds\": [", size_t(mesh.n_vertices()),
              size_t(mesh.n_faces()));
  for (size_t i = 0; i < seconds.size(); ++i) std::printf("%s%.6f", i ? ", " : "", seconds[i]);
  std::printf("]}\n");
  return 0;
}

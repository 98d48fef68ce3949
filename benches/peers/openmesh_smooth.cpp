// OpenMesh's explicit Laplacian smoother, timed.
//
//   openmesh_smooth MESH.ply ITERATIONS REPS OUT_PREFIX
//
// JacobiLaplaceSmootherT with continuity C0 on a double-precision TriMesh:
//   uniform   component Tangential_and_Normal: uniform weights
//   cotangent component Normal: cotangent weights, computed once in initialize()
// OpenMesh fixes the step at 0.5 and never moves boundary vertices. Each repetition
// smooths a fresh copy of the input; initialize() (weights) and smooth() (iterations)
// are timed apart. Prints one JSON object per scheme on stdout and writes the last
// result's positions to OUT_PREFIX_SCHEME.xyz (raw little-endian doubles, 3 per
// vertex) for the agreement check. "whole" times the program a user would write: read
// the file, initialize, smooth, write a binary PLY (OUT_PREFIX_SCHEME.ply), per
// repetition. Build: g++ -O2 ... -lOpenMeshCore.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Smoother/JacobiLaplaceSmootherT.hh>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <string>
#include <vector>

struct DoubleTraits : public OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};
using Mesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;
using Smoother = OpenMesh::Smoother::JacobiLaplaceSmootherT<Mesh>;

static double wall() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
static double cpu() { return double(std::clock()) / CLOCKS_PER_SEC; }

static void print_list(const char* key, const std::vector<double>& v) {
  std::printf("\"%s\": [", key);
  for (size_t i = 0; i < v.size(); ++i) std::printf("%s%.6f", i ? ", " : "", v[i]);
  std::printf("]");
}

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: openmesh_smooth MESH.ply ITERATIONS REPS OUT_PREFIX\n");
    return 2;
  }
  const int iterations = std::atoi(argv[2]);
  const int reps = std::atoi(argv[3]);
  Mesh input;
  if (!OpenMesh::IO::read_mesh(input, argv[1])) {
    std::fprintf(stderr, "error: OpenMesh cannot read %s\n", argv[1]);
    return 1;
  }
  struct Scheme {
    const char* name;
    Smoother::Component component;
  };
  const Scheme schemes[] = {{"uniform", Smoother::Tangential_and_Normal},
                            {"cotangent", Smoother::Normal}};
  for (const Scheme& scheme : schemes) {
    std::vector<double> init, smooth, ratio;
    Mesh mesh;
    for (int r = 0; r < reps; ++r) {
      mesh = input;
      double w0 = wall();
      Smoother smoother(mesh);
      smoother.initialize(scheme.component, Smoother::C0);
      double w1 = wall(), c1 = cpu();
      smoother.smooth(iterations);
      double w2 = wall(), c2 = cpu();
      init.push_back(w1 - w0);
      smooth.push_back(w2 - w1);
      ratio.push_back((c2 - c1) / std::max(w2 - w1, 1e-9));
    }
    // The whole program a user would write: read the file, smooth, write a binary PLY.
    std::vector<double> whole;
    const std::string written = std::string(argv[4]) + "_" + scheme.name + ".ply";
    for (int r = 0; r < reps; ++r) {
      double w0 = wall();
      Mesh fresh;
      if (!OpenMesh::IO::read_mesh(fresh, argv[1])) return 1;
      Smoother smoother(fresh);
      smoother.initialize(scheme.component, Smoother::C0);
      smoother.smooth(iterations);
      if (!OpenMesh::IO::write_mesh(fresh, written, OpenMesh::IO::Options::Binary)) {
        std::fprintf(stderr, "error: OpenMesh cannot write %s\n", written.c_str());
        return 1;
      }
      whole.push_back(wall() - w0);
    }
    std::printf("{\"scheme\": \"%s\", \"vertices\": %zu, ", scheme.name, size_t(mesh.n_vertices()));
    print_list("initialize", init);
    std::printf(", ");
    print_list("smooth", smooth);
    std::printf(", ");
    print_list("cpu_wall", ratio);
    std::printf(", ");
    print_list("whole", whole);
    std::printf("}\n");
    std::fflush(stdout);
    std::ofstream out(std::string(argv[4]) + "_" + scheme.name + ".xyz", std::ios::binary);
    for (auto v : mesh.vertices()) out.write(reinterpret_cast<const char*>(mesh.point(v).data()), 24);
  }
  return 0;
}

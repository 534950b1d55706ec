// Automatic nodal breakdown timing: one line per mesh, best of 5 runs.
//   bench_automatic_nodes [MESH ...]   (default: the dense sample satellite, the NASA models
//                                       in ../shared/models/nasa, a 100k-face sphere)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <vector>

#include <fmt/core.h>

#include "thermodec/mesh/io.h"
#include "thermodec/nodes/automatic_nodes.h"

using namespace thermodec;

namespace {

// UV sphere of radius 1 with rings x segments quads (two triangles each): curved everywhere.
Mesh uv_sphere(int rings, int segments) {
  constexpr double kPi = 3.14159265358979323846;
  Mesh m;
  m.V.resize((rings + 1) * segments, 3);
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double theta = kPi * r / rings, phi = 2.0 * kPi * s / segments;
      m.V.row(r * segments + s) << std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
          std::cos(theta);
    }
  std::vector<Eigen::Vector3i> faces;
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const int a = r * segments + s, b = r * segments + (s + 1) % segments;
      const int c = a + segments, d = b + segments;
      if (r > 0) faces.emplace_back(a, c, b);           // poles: skip the zero-area half
      if (r < rings - 1) faces.emplace_back(b, c, d);
    }
  m.F.resize(faces.size(), 3);
  for (size_t i = 0; i < faces.size(); ++i) m.F.row(i) = faces[i].transpose();
  return m;
}

void run(const std::string& name, const Mesh& input) {
  double best_ms = 1e300;
  Mesh mesh;
  for (int i = 0; i < 5; ++i) {
    mesh = input;
    const auto start = std::chrono::steady_clock::now();
    assign_automatic_nodes(mesh);
    best_ms = std::min(best_ms, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  fmt::print("{}: {} faces -> {} nodes in {:.1f} ms\n", name, input.num_faces(), mesh.node_names.size(), best_ms);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::filesystem::path> files;
  for (int i = 1; i < argc; ++i) files.emplace_back(argv[i]);
  if (files.empty()) {
    const std::filesystem::path source(THERMODEC_SOURCE_DIR);
    files.push_back(source / "sample_models" / "satellite" / "satellite_dense.obj");
    const auto nasa = source / ".." / "shared" / "models" / "nasa";
    if (std::filesystem::is_directory(nasa))
      for (const char* name : {"tdrs.stl", "NPP_16.stl", "Juno.stl"}) files.push_back(nasa / name);
  }
  for (const auto& file : files) {
    MeshReadReport report;  // quiet about dropped degenerate faces
    run(file.filename().string(), read_mesh(file, {}, report));
  }
  if (argc == 1) run("uv_sphere_250x200", uv_sphere(250, 200));
  return 0;
}

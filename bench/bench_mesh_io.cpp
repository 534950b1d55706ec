// Mesh I/O throughput: write and read a wavy grid of ~1M triangles in every format, with
// welding on read. One line per case. Usage: bench_mesh_io [GRID_SIZE=708]; KEEP=1 keeps the
// files in $TMPDIR/thermodec_bench_mesh_io (use TMPDIR=/dev/shm to time parsing, not the disk).
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fmt/format.h>

#include "thermodec/mesh/io.h"

using namespace thermodec;
namespace fs = std::filesystem;

int main(int argc, char** argv) {
  const int n = argc > 1 ? std::atoi(argv[1]) : 708;  // (n-1)^2 * 2 triangles
  Mesh m;
  m.V.resize(n * n, 3);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) m.V.row(i * n + j) << i * 0.01, j * 0.01, 0.05 * std::sin(0.1 * i) * std::cos(0.07 * j);
  m.F.resize(2 * (n - 1) * (n - 1), 3);
  m.face_node.resize(m.F.rows());
  m.face_material.resize(m.F.rows());
  m.face_back_material = Eigen::VectorXi::Constant(m.F.rows(), -1);
  int f = 0;
  for (int i = 0; i + 1 < n; ++i)
    for (int j = 0; j + 1 < n; ++j) {
      const int a = i * n + j, b = a + 1, c = a + n, d = c + 1;
      for (auto tri : {Eigen::RowVector3i(a, b, d), Eigen::RowVector3i(a, d, c)}) {
        m.F.row(f) = tri;
        m.face_node[f] = (i * 4 / n) * 4 + j * 4 / n;  // 16 nodes
        m.face_material[f] = i % 2;
        ++f;
      }
    }
  for (int k = 0; k < 16; ++k) m.node_names.push_back(fmt::format("node_{:02}", k));
  m.material_names = {"paint", "osr"};

  const fs::path dir = fs::temp_directory_path() / "thermodec_bench_mesh_io";
  fs::create_directories(dir);
  struct Case { const char* file; bool binary; };
  for (const Case c : {Case{"grid.obj", false}, Case{"grid.ply", true}, Case{"ascii.ply", false},
                       Case{"grid.stl", true}, Case{"ascii.stl", false}}) {
    MeshWriteOptions w;
    w.binary = c.binary;
    auto t0 = std::chrono::steady_clock::now();
    write_mesh(dir / c.file, m, w);
    auto t1 = std::chrono::steady_clock::now();
    const Mesh back = read_mesh(dir / c.file);
    auto t2 = std::chrono::steady_clock::now();
    const double mb = fs::file_size(dir / c.file) / 1e6;
    fmt::print("{:<10} {} triangles -> {} triangles, {} vertices: write {:.0f} ms, read+weld {:.0f} ms ({:.1f} MB)\n",
               c.file, m.num_faces(), back.num_faces(), back.num_vertices(),
               std::chrono::duration<double, std::milli>(t1 - t0).count(),
               std::chrono::duration<double, std::milli>(t2 - t1).count(), mb);
  }
  if (!std::getenv("KEEP")) fs::remove_all(dir);
}

// `thermodec reduce` end to end on a small defective bare STL, the way a CAD export arrives:
// an L-shaped open sheet (two 1 m x 1 m panels at right angles, one-sided as exported) with
// some triangles written twice. The loader cleans it (duplicates dropped, the sheet made
// two-sided), automatic nodes (one per panel) and the default environment apply, and the
// default informed reduction must finish with a verified result (~20 s on 2 busy cores:
// every simulation carries the per-node ray budgets).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "common/cli_run.h"
#include "common/scratch_dir.h"
#include "thermodec/nodes/load_model.h"

using namespace thermodec;
namespace fs = std::filesystem;

namespace {

struct Tri {
  Eigen::Vector3d a, b, c;
};

// n x n grid over the quad (o, o + u, o + u + v, o + v), front along u x v.
void grid(std::vector<Tri>& out, const Eigen::Vector3d& o, const Eigen::Vector3d& u, const Eigen::Vector3d& v, int n) {
  auto p = [&](int i, int j) { return Eigen::Vector3d(o + u * (double(i) / n) + v * (double(j) / n)); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      out.push_back({p(i, j), p(i + 1, j), p(i + 1, j + 1)});
      out.push_back({p(i, j), p(i + 1, j + 1), p(i, j + 1)});
    }
}

std::string ascii_stl(const std::vector<Tri>& tris) {
  std::ostringstream s;
  s.precision(17);
  s << "solid defective\n";
  for (const Tri& t : tris) {
    const Eigen::Vector3d n = (t.b - t.a).cross(t.c - t.a).normalized();
    s << " facet normal " << n.x() << " " << n.y() << " " << n.z() << "\n  outer loop\n";
    for (const auto& p : {t.a, t.b, t.c}) s << "   vertex " << p.x() << " " << p.y() << " " << p.z() << "\n";
    s << "  endloop\n endfacet\n";
  }
  s << "endsolid defective\n";
  return s.str();
}

}  // namespace

TEST(ReduceBareMesh, defective_stl_with_duplicates_and_an_open_sheet_reduces_with_a_verified_result) {
  const fs::path dir = thermodec::test::scratch_dir("thermodec_test_reduce_bare", "mesh");
  std::vector<Tri> tris;
  const Eigen::Vector3d X(1, 0, 0), Y(0, 1, 0), Z(0, 0, 1), O(0, 0, 0);
  grid(tris, O, X, Y, 4);  // floor panel, facing +z
  grid(tris, O, Z, X, 4);  // wall panel, facing +y
  const int sheet_faces = static_cast<int>(tris.size());
  for (int k = 0; k < 6; ++k) tris.push_back(tris[5 * k]);  // 6 triangles written twice
  std::ofstream(dir / "defective.stl") << ascii_stl(tris);

  const fs::path out = dir / "out";
  using thermodec::test::q;
  const thermodec::test::CliRun r =
      thermodec::test::run_cli("reduce " + q(dir / "defective.stl") + " --output " + q(out) + " --no-plots", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("duplicate faces dropped: 6"), std::string::npos) << r.out;

  const auto j = nlohmann::json::parse(std::ifstream(out / "report.json"));
  ASSERT_TRUE(j.contains("mesh_cleanup"));
  EXPECT_EQ(j["mesh_cleanup"]["faces_in"].get<int>(), sheet_faces + 6);
  EXPECT_EQ(j["mesh_cleanup"]["duplicate_faces_dropped"].get<int>(), 6);
  EXPECT_EQ(j["mesh_cleanup"]["open_sheet_faces_made_two_sided"].get<int>(), sheet_faces);
  EXPECT_EQ(j["mesh_cleanup"]["open_sheets"].get<int>(), 1);
  EXPECT_EQ(j["faces_before"].get<int>(), sheet_faces);
  EXPECT_LT(j["faces_after"].get<int>(), j["faces_before"].get<int>());
  EXPECT_LE(j["max_temperature_difference_K"].get<double>(), j["tolerance_K"].get<double>());
  EXPECT_LT(2 * j["noise_floor_K"].get<double>(), j["tolerance_K"].get<double>());

  // The reduced model keeps the sheet two-sided (a model file: loaded as written).
  const ThermalModel reduced = load_model(out / "model.json");
  EXPECT_EQ(reduced.mesh.num_faces(), j["faces_after"].get<int>());
  int two_sided = 0;
  for (int f = 0; f < reduced.mesh.num_faces(); ++f) two_sided += reduced.mesh.is_two_sided(f);
  EXPECT_GT(two_sided, 0);
  if (!HasFailure()) fs::remove_all(dir);
}

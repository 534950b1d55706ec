// `thermodec viewfactors` and `thermodec external` end to end.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include <sys/wait.h>

#include "analytic.h"
#include "common/cli_run.h"

namespace fs = std::filesystem;

namespace {

using thermodec::test::read_text;
using thermodec::test::run_cli_logged;
using thermodec::test::temp_dir;

// Two 1 x 1 m plates 1 m apart facing each other, as OBJ groups, 2 x 2 quads each.
void write_two_plates(const fs::path& path) {
  std::ofstream o(path);
  for (int p = 0; p < 2; ++p)
    for (int i = 0; i <= 2; ++i)
      for (int j = 0; j <= 2; ++j) o << "v " << i * 0.5 << " " << j * 0.5 << " " << p << "\n";
  for (int p = 0; p < 2; ++p) {
    o << "g plate" << p << "\n";
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) {
        const int a = 1 + p * 9 + i * 3 + j, b = a + 3, c = a + 4, d = a + 1;
        if (p == 0) o << "f " << a << " " << b << " " << c << "\nf " << a << " " << c << " " << d << "\n";
        else o << "f " << a << " " << c << " " << b << "\nf " << a << " " << d << " " << c << "\n";
      }
  }
}

}  // namespace

TEST(ViewFactorsCli, plain_obj_of_two_plates_gives_the_catalog_factor_and_all_keys) {
  const fs::path dir = temp_dir("cli_vf");
  write_two_plates(dir / "plates.obj");
  ASSERT_EQ(run_cli_logged("viewfactors " + (dir / "plates.obj").string() + " --json " + (dir / "vf.json").string(), dir / "log"), 0)
      << read_text(dir / "log");
  const auto j = nlohmann::json::parse(read_text(dir / "vf.json"));
  for (const char* key : {"nodes", "area_m2", "view_factors", "to_space", "radiative_couplings_m2", "to_space_couplings_m2",
                          "standard_error"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_TRUE(j["standard_error"].contains("view_factors"));
  EXPECT_TRUE(j["standard_error"].contains("radiative_couplings_m2"));
  ASSERT_EQ(j["nodes"].size(), 2u);
  EXPECT_EQ(j["nodes"][0], "plate0");
  const double F01 = j["view_factors"][0][1], se = j["standard_error"]["view_factors"][0][1];
  const double exact = thermodec::test::parallel_rectangles(1, 1, 1);
  EXPECT_NEAR(F01, exact, 5 * se);
  EXPECT_NEAR(F01, exact, 0.01 * exact);
  // As in `simulate`, the plates' hulls are control variates: nothing hides one from the
  // other, so the factor is exact up to the rays' origin lift (1e-5 x coordinate magnitude).
  EXPECT_NEAR(F01, exact, 1e-5);
  EXPECT_NEAR(double(j["area_m2"][1]), 1.0, 1e-12);
  EXPECT_EQ(j["radiative_couplings_m2"][0][1], j["radiative_couplings_m2"][1][0]);
}

TEST(ViewFactorsCli, missing_model_exits_1_with_a_message) {
  const fs::path dir = temp_dir("cli_missing");
  EXPECT_EQ(run_cli_logged("viewfactors " + (dir / "nope.obj").string() + " --json " + (dir / "vf.json").string(), dir / "log"), 1);
  EXPECT_NE(read_text(dir / "log").find("nope.obj"), std::string::npos) << read_text(dir / "log");
  EXPECT_FALSE(fs::exists(dir / "vf.json"));
}

TEST(ExternalCli, writes_the_external_mesh_and_refuses_to_overwrite_its_input) {
  const fs::path dir = temp_dir("cli_ext");
  write_two_plates(dir / "plates.obj");
  ASSERT_EQ(run_cli_logged("external " + (dir / "plates.obj").string() + " -o " + (dir / "ext.obj").string(), dir / "log"), 0)
      << read_text(dir / "log");
  EXPECT_TRUE(fs::exists(dir / "ext.obj"));
  EXPECT_NE(read_text(dir / "log").find("plate0"), std::string::npos);
  EXPECT_EQ(run_cli_logged("external " + (dir / "plates.obj").string() + " -o " + (dir / "plates.obj").string(), dir / "log2"), 1);
  // A model output (.json + .obj beside it) is a valid MODEL for the next step.
  ASSERT_EQ(run_cli_logged("external " + (dir / "plates.obj").string() + " -o " + (dir / "ext" / "model.json").string(), dir / "log3"), 0)
      << read_text(dir / "log3");
  EXPECT_TRUE(fs::exists(dir / "ext" / "model.obj"));
  EXPECT_EQ(run_cli_logged("viewfactors " + (dir / "ext" / "model.json").string() + " --rays 200 --json " + (dir / "vf.json").string(),
                dir / "log4"), 0) << read_text(dir / "log4");
}

TEST(SharedModelsRadiation, nasa_models_run_through_viewfactors_and_external) {
  const fs::path nasa = fs::path(THERMODEC_SHARED_DIR) / "models" / "nasa";
  if (!fs::exists(nasa / "NPP_16.stl")) GTEST_SKIP() << "no " << nasa;
  const fs::path dir = temp_dir("cli_nasa");
  ASSERT_EQ(run_cli_logged("viewfactors " + (nasa / "NPP_16.stl").string() + " --rays 64 --json " + (dir / "vf.json").string(),
                dir / "log"), 0) << read_text(dir / "log");
  const auto j = nlohmann::json::parse(read_text(dir / "vf.json"));
  EXPECT_GE(j["nodes"].size(), 1u);
  ASSERT_EQ(run_cli_logged("external " + (nasa / "NPP_16.stl").string() + " -o " + (dir / "ext.stl").string(), dir / "log2"), 0)
      << read_text(dir / "log2");
  EXPECT_TRUE(fs::exists(dir / "ext.stl"));
}

// `thermodec nodes` end to end: exit codes, the written grouped mesh, refusal to overwrite.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/wait.h>

#include "common/cli_run.h"
#include "thermodec/mesh/io.h"

using namespace thermodec;

namespace {

// One folder per test, so that ctest may run them in parallel.
std::filesystem::path scratch_dir() {
  return thermodec::test::scratch_dir("thermodec_test_cmd_nodes",
                                      ::testing::UnitTest::GetInstance()->current_test_info()->name());
}

const std::filesystem::path kSatellite =
    std::filesystem::path(THERMODEC_SOURCE_DIR) / "sample_models" / "satellite" / "satellite.obj";

using thermodec::test::read_text;
using thermodec::test::run_cli;

}  // namespace

TEST(CmdNodes, writes_grouped_mesh_and_prints_one_line_per_node) {
  const auto dir = scratch_dir();
  const auto out = dir / "auto.obj";
  ASSERT_EQ(run_cli("nodes \"" + kSatellite.string() + "\" -o \"" + out.string() + "\" --max-nodes 12", dir).exit_code, 0)
      << read_text(dir / "stderr");
  const Mesh mesh = read_mesh(out);
  EXPECT_EQ(mesh.num_faces(), 882);
  ASSERT_EQ(mesh.node_names.size(), 12u);
  EXPECT_EQ(mesh.node_names.front(), "node_000");
  EXPECT_EQ(mesh.node_names.back(), "node_011");
  EXPECT_GE(mesh.face_node.minCoeff(), 0);
  // Coatings survive the regrouping.
  EXPECT_EQ(mesh.material_names.size(), 5u);
  const std::string printed = read_text(dir / "stdout");
  EXPECT_NE(printed.find("882 faces -> 12 nodes"), std::string::npos) << printed;
  EXPECT_NE(printed.find("node_011"), std::string::npos) << printed;
}

TEST(CmdNodes, same_input_gives_byte_identical_output) {
  const auto dir = scratch_dir();
  ASSERT_EQ(run_cli("nodes \"" + kSatellite.string() + "\" -o \"" + (dir / "a.ply").string() + "\"", dir).exit_code, 0);
  ASSERT_EQ(run_cli("nodes \"" + kSatellite.string() + "\" -o \"" + (dir / "b.ply").string() + "\"", dir).exit_code, 0);
  EXPECT_EQ(read_text(dir / "a.ply"), read_text(dir / "b.ply"));
}

TEST(CmdNodes, refuses_to_overwrite_its_input) {
  const auto dir = scratch_dir();
  const auto copy = dir / "input.obj";
  std::filesystem::copy_file(kSatellite, copy);
  const std::string before = read_text(copy);
  EXPECT_EQ(run_cli("nodes \"" + copy.string() + "\" -o \"" + copy.string() + "\"", dir).exit_code, 1);
  EXPECT_EQ(read_text(copy), before);
  EXPECT_FALSE(read_text(dir / "stderr").empty());
}

TEST(CmdNodes, missing_input_fails_with_one_line_reason) {
  const auto dir = scratch_dir();
  EXPECT_EQ(run_cli("nodes \"" + (dir / "absent.stl").string() + "\" -o \"" + (dir / "out.obj").string() + "\"", dir).exit_code, 1);
  const std::string err = read_text(dir / "stderr");
  EXPECT_NE(err.find("absent.stl"), std::string::npos) << err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out.obj"));
}

TEST(CmdNodes, zero_angle_is_rejected) {
  const auto dir = scratch_dir();
  EXPECT_EQ(run_cli("nodes \"" + kSatellite.string() + "\" -o \"" + (dir / "out.obj").string() + "\" --max-angle 0", dir).exit_code, 1);
  EXPECT_NE(read_text(dir / "stderr").find("max_normal_deviation_deg"), std::string::npos);
}

TEST(CmdNodes, model_file_input_keeps_coatings_and_protects_its_mesh) {
  const auto dir = scratch_dir();
  const auto model = kSatellite.parent_path() / "model.json";
  const auto out = dir / "auto.ply";
  ASSERT_EQ(run_cli("nodes \"" + model.string() + "\" -o \"" + out.string() + "\"", dir).exit_code, 0)
      << read_text(dir / "stderr");
  const Mesh mesh = read_mesh(out);
  EXPECT_EQ(mesh.num_faces(), 882);
  EXPECT_GE(mesh.face_material.minCoeff(), 0);
  EXPECT_GT(mesh.face_back_material.maxCoeff(), -1);  // wings, yokes and dish stay two-sided
  EXPECT_EQ(run_cli("nodes \"" + model.string() + "\" -o \"" + kSatellite.string() + "\"", dir).exit_code, 1);
}

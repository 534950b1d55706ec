// Runs that would take hours are refused before the work, naming the setting and the estimate
// (thermal/simulation_cost.h), unless the global --force is given; every simulating command
// prints its estimate.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "common/cli_run.h"

namespace fs = std::filesystem;

namespace {

using namespace thermodec::test;

const fs::path kData = THERMODEC_TEST_DATA_DIR;
const fs::path kSample = fs::path(THERMODEC_SOURCE_DIR) / "sample_models" / "satellite";


// The sample satellite (882 faces) with radiation.rays_per_face at its maximum, 10^7.
fs::path sample_with_rays_at_maximum(const fs::path& d) {
  fs::copy_file(kSample / "satellite.obj", d / "satellite.obj");
  nlohmann::json m = nlohmann::json::parse(read_text(kSample / "model.json"));
  m["radiation"]["rays_per_face"] = 10000000;
  std::ofstream(d / "model.json") << m.dump(1);
  return d / "model.json";
}

// The 12-face example model on an orbit, orbit transient with `positions` load positions.
fs::path cube_on_orbit(const fs::path& d, int positions) {
  fs::copy_file(kData / "satellite.obj", d / "satellite.obj", fs::copy_options::overwrite_existing);
  nlohmann::json m = nlohmann::json::parse(read_text(kData / "example_model.json"));
  m["environment"] = {{"type", "orbit"}};
  m["analysis"] = {{"type", "transient_orbit"}, {"steps_per_orbit", positions}};
  const fs::path p = d / ("cube_" + std::to_string(positions) + ".json");
  std::ofstream(p) << m.dump(1);
  return p;
}

void expect_refused(const CliRun& r, const std::string& knob) {
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(has(r.err, "thermodec: invalid input: estimated cost")) << r.err;
  EXPECT_TRUE(has(r.err, "over the limit")) << r.err;
  EXPECT_TRUE(has(r.err, knob)) << r.err;
  EXPECT_TRUE(has(r.err, "--force")) << r.err;
}

}  // namespace

TEST(CliCostChecks, rays_per_face_at_its_maximum_on_the_sample_is_refused_by_every_simulating_command) {
  const auto d = temp_dir("rays");
  const fs::path m = sample_with_rays_at_maximum(d);
  const std::string knob = "radiation.rays_per_face = 10000000";
  expect_refused(run_cli("simulate " + q(m) + " --json " + q(d / "r.json"), d), knob);
  EXPECT_FALSE(fs::exists(d / "r.json"));
  expect_refused(run_cli("viewfactors " + q(m) + " --json " + q(d / "vf.json"), d), knob);
  expect_refused(run_cli("export " + q(m) + " --format csv -o " + q(d / "tables"), d), knob);
  expect_refused(run_cli("reduce " + q(m) + " --out " + q(d / "reduced"), d), knob);
  EXPECT_FALSE(fs::exists(d / "reduced" / "report.json"));
  // The estimate names the rays: 1374 sides x 2^23 (10^7 rounded to a power of two).
  const CliRun r = run_cli("viewfactors " + q(m) + " --json " + q(d / "vf.json"), d);
  EXPECT_TRUE(has(r.err, "1.2e+10 rays to trace (limit 1e+10)")) << r.err;
  // The NASTRAN export simulates nothing: no estimate, no refusal.
  const CliRun nastran = run_cli("export " + q(m) + " --format nastran -o " + q(d / "mesh.bdf") + " -q", d);
  EXPECT_EQ(nastran.exit_code, 0) << nastran.err;
  EXPECT_TRUE(fs::exists(d / "mesh.bdf"));
}

TEST(CliCostChecks, a_million_orbit_positions_on_a_12_face_model_is_refused_naming_the_setting) {
  const auto d = temp_dir("positions");
  expect_refused(run_cli("simulate -q " + q(cube_on_orbit(d, 1000000)), d), "analysis.steps_per_orbit = 1000000");
  // The same through the command-line override of a reasonable model.
  expect_refused(run_cli("simulate " + q(cube_on_orbit(d, 72)) + " --load-positions 1000000", d), "1000000 load positions");
  // 10^5 positions: the thermal solver (3 x 10^12 units of work) is what exceeds (without the
  // second run and extra samples of noise-targeted sampling, which put the rays over first).
  expect_refused(run_cli("simulate " + q(cube_on_orbit(d, 100000)) + " --noise-target 0", d), "thermal solver work");
}

TEST(CliCostChecks, a_load_case_over_the_limit_is_refused_by_reduce_and_named) {
  const auto d = temp_dir("case");
  std::ofstream(d / "long.json") << R"({"name": "long", "analysis": {"type": "transient_orbit", "steps_per_orbit": 1000000}})";
  const CliRun r = run_cli("reduce " + q(cube_on_orbit(d, 24)) + " --case " + q(d / "long.json") + " --out " +
                               q(d / "reduced"),
                           d);
  expect_refused(r, "analysis.steps_per_orbit = 1000000");
  EXPECT_TRUE(has(r.err, "estimated cost (case long) over the limit")) << r.err;
}

TEST(CliCostChecks, force_runs_it_anyway_with_a_warning) {
  const auto d = temp_dir("force");
  // Over the solver limit only; stopped by `timeout` once it is past the check.
  const CliRun r = run_cli("simulate -q " + q(cube_on_orbit(d, 100000)) + " --noise-target 0 --force", d, "timeout 4");
  EXPECT_EQ(r.exit_code, 124) << "not refused, still running when stopped: " << r.err;
  EXPECT_TRUE(has(r.err, "simulate: warning: estimated cost over the limit, running anyway (--force)")) << r.err;
  EXPECT_TRUE(has(r.err, "thermal solver work")) << r.err;
}

TEST(CliCostChecks, simulating_commands_print_their_estimate_and_quiet_hides_it) {
  const auto d = temp_dir("print");
  const fs::path m = kData / "example_model.json";
  CliRun r = run_cli("simulate " + q(m) + " --noise-target 0", d);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(has(r.err, "simulate: estimated cost: ")) << r.err;
  // 12 faces: 2 nodes x 250 000 (min_rays_per_node), each side's share rounded to a power of two
  EXPECT_TRUE(has(r.err, "rays (IR 5.9e+05")) << r.err;
  EXPECT_TRUE(has(r.err, "steady solve x 2 nodes")) << r.err;
  r = run_cli("simulate -q " + q(m) + " --noise-target 0", d);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(has(r.err, "estimated cost")) << r.err;
  r = run_cli("viewfactors " + q(m) + " --json " + q(d / "vf.json"), d);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(has(r.err, "viewfactors: estimated cost: 5.9e+05 rays (IR 5.9e+05); memory")) << r.err;
}

TEST(CliCostChecks, help_documents_force_and_the_limits) {
  const auto d = temp_dir("help");
  const CliRun r = run_cli("--help", d);
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_TRUE(has(r.out, "--force")) << r.out;
  EXPECT_TRUE(has(r.out, "1e+10 rays traced")) << r.out;
  EXPECT_TRUE(has(r.out, "16 GiB")) << r.out;
}

namespace {

// A flat plate of 2 n^2 triangles in a model file with `rays` IR rays per face.
fs::path plate_model(const fs::path& d, int n, int rays) {
  std::string obj;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) obj += "v " + std::to_string(i) + " " + std::to_string(j) + " 0\n";
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i + 1, b = a + 1, c = a + n + 1, e = c + 1;
      obj += "f " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(e) + "\nf " + std::to_string(a) +
             " " + std::to_string(e) + " " + std::to_string(c) + "\n";
    }
  write_text(d / "plate.obj", obj);
  write_text(d / "plate.json", "{\"mesh\": \"plate.obj\", \"radiation\": {\"rays_per_face\": " + std::to_string(rays) + "}}");
  return d / "plate.json";
}

}  // namespace

TEST(CliCostChecks, view_factor_rows_beyond_the_machines_memory_are_refused_unless_forced) {
  const auto d = temp_dir("rows");
  // 100 352 faces x 90 000 rays: 9e9 rays, under the ray limit; rows up to 12 B x 9e4 x 1e5 = 101 GiB.
  const fs::path m = plate_model(d, 224, 90000);
  const CliRun r = run_cli("simulate " + q(m) + " --noise-target 0 --json " + q(d / "r.json"), d, "timeout 120");
  if (has(r.err, "running anyway")) GTEST_SKIP() << "this machine has more memory than the bound";
  expect_refused(r, "view-factor rows up to");
  EXPECT_TRUE(has(r.err, "this machine's")) << r.err;
}

TEST(CliCostChecks, the_estimate_includes_noise_targeted_sampling) {
  const auto d = temp_dir("noise_boosts");
  // 1374 sides x 5e6 = 6.9e9 IR rays at the model's counts: within the limit once, over it
  // with the estimating run and the extra samples the noise targeting may add.
  fs::copy_file(kSample / "satellite.obj", d / "satellite.obj");
  nlohmann::json m = nlohmann::json::parse(read_text(kSample / "model.json"));
  m["radiation"]["rays_per_face"] = 5000000;
  std::ofstream(d / "model.json") << m.dump(1);
  const CliRun r = run_cli("simulate " + q(d / "model.json") + " --json " + q(d / "r.json"), d, "timeout 120");
  EXPECT_TRUE(has(r.err, "estimated cost with noise-targeted sampling")) << r.err;
  expect_refused(r, "rays to trace");
}

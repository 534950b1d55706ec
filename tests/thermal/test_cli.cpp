// `thermodec simulate` / `thermodec compare` end to end on the sample satellite.
#include <cmath>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/cli_run.h"

namespace fs = std::filesystem;

namespace {
using thermodec::test::read_text;
using thermodec::test::run_cli_logged;
using thermodec::test::temp_dir;
const fs::path kSatellite = fs::path(THERMODEC_SOURCE_DIR) / "sample_models/satellite/model.json";
}  // namespace

TEST(SimulateCli, sample_satellite_orbit_writes_result_json_plot_and_compares_to_itself) {
  const fs::path d = temp_dir("cli");
  ASSERT_EQ(run_cli_logged("simulate " + kSatellite.string() + " --json " + (d / "a.json").string() + " --plot " +
                    (d / "a.png").string(),
                d / "log.txt"),
            0)
      << read_text(d / "log.txt");
  EXPECT_NE(read_text(d / "log.txt").find("orbit 1"), std::string::npos);  // progress on stderr
  const nlohmann::json j = nlohmann::json::parse(read_text(d / "a.json"));
  const auto nodes = j.at("nodes").get<std::vector<std::string>>();
  ASSERT_EQ(nodes.size(), 13u);
  const auto times = j.at("times_s").get<std::vector<double>>();
  EXPECT_EQ(times.size(), 120u);  // the sample's analysis.steps_per_orbit
  EXPECT_EQ(j.at("analysis"), "transient_orbit");
  for (const auto& n : nodes) {
    EXPECT_EQ(j.at("temperatures_K").at(n).size(), times.size()) << n;
    const auto& s = j.at("summary").at(n);
    EXPECT_LE(s.at("min_K").get<double>(), s.at("mean_K").get<double>());
    EXPECT_LE(s.at("mean_K").get<double>(), s.at("max_K").get<double>());
    EXPECT_GT(s.at("min_K").get<double>(), 150.0) << n;  // a sane spacecraft, not garbage
    EXPECT_LT(s.at("max_K").get<double>(), 450.0) << n;
    EXPECT_EQ(j.at("loads_W").at(n).at("solar").size(), times.size());
  }
  EXPECT_LE(j.at("solver").at("periodicity_residual_K").get<double>(), 1e-3);
  EXPECT_LT(j.at("solver").at("energy_last_orbit_J").at("relative_imbalance").get<double>(), 1e-3);
  EXPECT_GT(fs::file_size(d / "a.png"), 10000u);

  // Same seed: bit-identical temperatures, compare says 0.
  ASSERT_EQ(run_cli_logged("simulate -q " + kSatellite.string() + " --json " + (d / "b.json").string(), d / "log2.txt"), 0);
  EXPECT_EQ(nlohmann::json::parse(read_text(d / "b.json")).at("temperatures_K"), j.at("temperatures_K"));
  ASSERT_EQ(run_cli_logged("compare " + (d / "a.json").string() + " " + (d / "b.json").string(), d / "cmp.txt"), 0);
  EXPECT_NE(read_text(d / "cmp.txt").find("max |dT| = 0 K"), std::string::npos) << read_text(d / "cmp.txt");
}

TEST(CompareCli, reports_node_and_time_of_the_largest_difference_and_rejects_mismatched_nodes) {
  const fs::path d = temp_dir("cmp");
  nlohmann::json a = {{"nodes", {"x", "y"}},
                      {"times_s", {0.0, 60.0, 120.0}},
                      {"temperatures_K", {{"x", {300.0, 301.0, 302.0}}, {"y", {250.0, 250.0, 250.0}}}}};
  nlohmann::json b = a;
  b["temperatures_K"]["y"] = {250.0, 249.75, 250.1};
  std::ofstream(d / "a.json") << a.dump();
  std::ofstream(d / "b.json") << b.dump();
  ASSERT_EQ(run_cli_logged("compare --json " + (d / "a.json").string() + " " + (d / "b.json").string(), d / "out.txt"), 0);
  const nlohmann::json r = nlohmann::json::parse(read_text(d / "out.txt"));
  EXPECT_NEAR(r.at("max_abs_dT_K").get<double>(), 0.25, 1e-12);
  EXPECT_EQ(r.at("node"), "y");
  EXPECT_EQ(r.at("time_s").get<double>(), 60.0);
  b["nodes"] = {"x", "z"};
  b["temperatures_K"]["z"] = b["temperatures_K"]["y"];
  std::ofstream(d / "c.json") << b.dump();
  EXPECT_EQ(run_cli_logged("compare " + (d / "a.json").string() + " " + (d / "c.json").string(), d / "err.txt"), 1);
  EXPECT_NE(read_text(d / "err.txt").find("'z'"), std::string::npos) << read_text(d / "err.txt");
  EXPECT_EQ(run_cli_logged("compare " + (d / "a.json").string() + " " + (d / "missing.json").string(), d / "err2.txt"), 1);
}

TEST(SimulateCli, refuses_to_overwrite_its_input) {
  const fs::path d = temp_dir("overwrite");
  fs::copy_file(kSatellite, d / "model.json");
  fs::copy_file(kSatellite.parent_path() / "satellite.obj", d / "satellite.obj");
  EXPECT_EQ(run_cli_logged("simulate -q " + (d / "model.json").string() + " --json " + (d / "model.json").string(), d / "log.txt"), 1);
  EXPECT_EQ(read_text(d / "model.json"), read_text(kSatellite));
}

TEST(SimulateCli, noise_floor_reports_max_difference_between_seeds_and_run_time) {
  const fs::path d = temp_dir("noise");
  ASSERT_EQ(run_cli_logged("simulate -q " + kSatellite.string() + " --noise-floor --noise-runs 3 --rays 500 --earth-rays 512 --noise-budget 2 "
                "--json " + (d / "n.json").string(),
                d / "out.txt"),
            0)
      << read_text(d / "out.txt");
  const std::string out = read_text(d / "out.txt");
  EXPECT_NE(out.find("noise floor over 3 seeds (1..3), all 3 pairs: max |dT| = "), std::string::npos) << out;
  EXPECT_NE(out.find("median pair "), std::string::npos) << out;
  EXPECT_NE(out.find("run time: "), std::string::npos) << out;
  const nlohmann::json j = nlohmann::json::parse(read_text(d / "n.json"));
  const double dT = j.at("noise_floor").at("max_abs_dT_K").get<double>();
  EXPECT_GT(dT, 0.0);   // different seeds do differ...
  EXPECT_LT(dT, 0.5);   // ...by Monte Carlo noise only (500 rays per face)
  EXPECT_EQ(j.at("noise_floor").at("run_time_s").size(), 3u);
  // every pair, not only each run against the first: 1-2, 1-3 and 2-3
  EXPECT_EQ(j.at("noise_floor").at("pairs").get<int>(), 3);
  const double median = j.at("noise_floor").at("median_pair_max_abs_dT_K").get<double>();
  EXPECT_GT(median, 0.0);
  EXPECT_LE(median, dT);
  const auto seeds = j.at("noise_floor").at("worst_seeds").get<std::vector<int>>();
  ASSERT_EQ(seeds.size(), 2u);
  EXPECT_LT(seeds[0], seeds[1]);
  // Every node's own worst pair; the largest of them is the floor, on the floor's node.
  EXPECT_NE(out.find("worst pair per node [K]: "), std::string::npos) << out;
  const auto& per_node = j.at("noise_floor").at("per_node");
  EXPECT_EQ(per_node.size(), j.at("nodes").size());
  double largest = 0.0;
  for (const auto& [name, w] : per_node.items()) {
    EXPECT_LE(w.at("max_abs_dT_K").get<double>(), dT) << name;
    largest = std::max(largest, w.at("max_abs_dT_K").get<double>());
    EXPECT_EQ(w.at("seeds").size(), 2u) << name;
  }
  EXPECT_EQ(largest, dT);
  EXPECT_EQ(per_node.at(j.at("noise_floor").at("node").get<std::string>()).at("max_abs_dT_K").get<double>(), dT);
}

TEST(CompareCli, marks_differences_within_two_sigma_of_the_results_noise) {
  // x differs by 0.01 K with noise 0.004 K in each result (0.0057 K for the difference): within
  // 2 sigma; y differs by 0.25 K: not. Results without noise_K are compared as before.
  const fs::path d = temp_dir("cmp_noise");
  nlohmann::json a = {{"nodes", {"x", "y"}},
                      {"times_s", {0.0, 60.0}},
                      {"temperatures_K", {{"x", {300.0, 301.0}}, {"y", {250.0, 250.0}}}},
                      {"summary", {{"x", {{"noise_K", 0.004}}}, {"y", {{"noise_K", 0.004}}}}}};
  nlohmann::json b = a;
  b["temperatures_K"]["x"] = {300.01, 301.0};
  b["temperatures_K"]["y"] = {250.25, 250.0};
  std::ofstream(d / "a.json") << a.dump();
  std::ofstream(d / "b.json") << b.dump();
  ASSERT_EQ(run_cli_logged("compare --json " + (d / "a.json").string() + " " + (d / "b.json").string(), d / "out.txt"), 0);
  const nlohmann::json r = nlohmann::json::parse(read_text(d / "out.txt"));
  EXPECT_NEAR(r.at("nodes").at(0).at("noise_K").get<double>(), std::sqrt(2.0) * 0.004, 1e-12);
  EXPECT_TRUE(r.at("nodes").at(0).at("within_2_sigma_noise").get<bool>());
  EXPECT_FALSE(r.at("nodes").at(1).at("within_2_sigma_noise").get<bool>());
  ASSERT_EQ(run_cli_logged("compare " + (d / "a.json").string() + " " + (d / "b.json").string(), d / "table.txt"), 0);
  const std::string table = read_text(d / "table.txt");
  EXPECT_NE(table.find("within 2 sigma of noise"), std::string::npos) << table;
  a.erase("summary");
  std::ofstream(d / "c.json") << a.dump();
  ASSERT_EQ(run_cli_logged("compare --json " + (d / "c.json").string() + " " + (d / "b.json").string(), d / "out2.txt"), 0);
  EXPECT_TRUE(nlohmann::json::parse(read_text(d / "out2.txt")).at("nodes").at(0).contains("noise_K"));  // b's alone
}

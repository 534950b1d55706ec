// Bad inputs and bad output paths are refused by name, before any work, with exit code 1;
// inputs are never overwritten; a reduce folder holds only its own outputs.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "common/cli_run.h"

namespace fs = std::filesystem;

namespace {

using namespace thermodec::test;

const fs::path kData = THERMODEC_TEST_DATA_DIR;

// The 12-face example model with `extra` spliced in as further top-level keys.
fs::path model_with(const fs::path& d, const std::string& extra, const std::string& name = "model.json") {
  fs::copy_file(kData / "satellite.obj", d / "satellite.obj", fs::copy_options::overwrite_existing);
  std::string text = read_text(kData / "example_model.json");
  text.insert(text.find('{') + 1, extra);
  write_text(d / name, text);
  return d / name;
}

}  // namespace

TEST(CliInputChecks, misspelt_top_level_key_is_an_error_with_a_suggestion) {
  auto d = temp_dir("typo");
  const auto m = model_with(d, "\"enviroment\": {\"type\": \"orbit\"},");
  const CliRun r = run_cli("info " + q(m), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.err, "'enviroment'")) << r.err;
  EXPECT_TRUE(has(r.err, "did you mean 'environment'")) << r.err;
}

TEST(CliInputChecks, allow_unknown_keys_downgrades_the_error_to_a_warning) {
  auto d = temp_dir("allow");
  const auto m = model_with(d, "\"enviroment\": {\"type\": \"orbit\"},");
  const CliRun r = run_cli("info --allow-unknown-keys " + q(m), d);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(has(r.err, "warning")) << r.err;
}

TEST(CliInputChecks, nodes_option_caps_the_automatic_breakdown_of_a_mesh_without_groups) {
  auto d = temp_dir("nodes_cap");
  std::istringstream grouped(read_text(kData / "satellite.obj"));
  std::string bare;
  for (std::string line; std::getline(grouped, line);)
    if (line.rfind("g ", 0) != 0 && line.rfind("usemtl", 0) != 0 && line.rfind("o ", 0) != 0) bare += line + "\n";
  write_text(d / "bare.obj", bare);
  const CliRun r = run_cli("info --nodes 4 " + q(d / "bare.obj"), d);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(has(r.out, "nodes               4\n")) << r.out;
  const CliRun zero = run_cli("info --nodes 0 " + q(d / "bare.obj"), d);
  EXPECT_EQ(zero.exit_code, 1);
  EXPECT_TRUE(has(zero.err, "--nodes")) << zero.err;
}

TEST(CliInputChecks, misspelt_nested_key_names_the_nearest_known_key) {
  auto d = temp_dir("nested_typo");
  fs::copy_file(kData / "satellite.obj", d / "satellite.obj");
  std::string text = read_text(kData / "example_model.json");
  const auto at = text.find("\"rays_per_face\"");
  text.replace(at, 15, "\"rays_per_fase\"");
  write_text(d / "model.json", text);
  const CliRun r = run_cli("info " + q(d / "model.json"), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.err, "did you mean 'rays_per_face'")) << r.err;
}

TEST(CliInputChecks, duplicate_keys_are_refused) {
  auto d = temp_dir("dup");
  const auto m = model_with(d, "\"radiation\": {\"seed\": 2},");
  const CliRun r = run_cli("info " + q(m), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.err, "'radiation' appears twice")) << r.err;
}

TEST(CliInputChecks, deeply_nested_json_is_refused_without_a_crash) {
  auto d = temp_dir("deep");
  std::string text = read_text(kData / "example_model.json");
  const auto at = text.find("\"seed\": 1");
  text.replace(at, 9, "\"seed\": " + std::string(100000, '[') + std::string(100000, ']'));
  fs::copy_file(kData / "satellite.obj", d / "satellite.obj");
  write_text(d / "model.json", text);
  const CliRun r = run_cli("info " + q(d / "model.json"), d);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(has(r.err, "nested deeper")) << r.err;
}

TEST(CliInputChecks, tiny_unit_scale_and_fixed_temperature_are_refused) {
  auto d = temp_dir("tiny");
  std::string text = read_text(kData / "example_model.json");
  text.replace(text.find("\"unit_scale\": 1.0"), 17, "\"unit_scale\": 1e-200");
  fs::copy_file(kData / "satellite.obj", d / "satellite.obj");
  write_text(d / "model.json", text);
  CliRun r = run_cli("simulate " + q(d / "model.json"), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.err, "unit_scale")) << r.err;
  text = read_text(kData / "example_model.json");
  text.replace(text.find("290.0"), 5, "1e-300");
  write_text(d / "model.json", text);
  r = run_cli("simulate " + q(d / "model.json"), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.err, "fixed_temperature")) << r.err;
}

TEST(CliInputChecks, min_rays_per_node_beyond_the_limit_is_refused_not_allocated) {
  auto d = temp_dir("rays");
  std::string text = read_text(kData / "example_model.json");
  text.replace(text.find("\"seed\": 1"), 9, "\"seed\": 1, \"min_rays_per_node\": 1000000000");
  fs::copy_file(kData / "satellite.obj", d / "satellite.obj");
  write_text(d / "model.json", text);
  const CliRun r = run_cli("simulate " + q(d / "model.json"), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.err, "min_rays_per_node")) << r.err;
}

TEST(CliInputChecks, material_name_with_a_newline_is_refused_at_load) {
  auto d = temp_dir("newline");
  std::string text = read_text(kData / "example_model.json");
  const std::string key = "\"white_paint\": {";
  text.replace(text.find(key), key.size(), "\"white\\npaint\": {");
  fs::copy_file(kData / "satellite.obj", d / "satellite.obj");
  write_text(d / "model.json", text);
  const CliRun r = run_cli("info " + q(d / "model.json"), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.err, "control characters")) << r.err;
}

TEST(CliInputChecks, mesh_path_that_is_a_device_or_fifo_is_refused) {
  auto d = temp_dir("device");
  fs::create_symlink("/dev/zero", d / "zero.stl");
  CliRun r = run_cli("info " + q(d / "zero.stl"), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.err, "not a regular file")) << r.err;
  ASSERT_EQ(::mkfifo((d / "pipe.obj").c_str(), 0600), 0);
  r = run_cli("info " + q(d / "pipe.obj"), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.err, "not a regular file")) << r.err;
}

TEST(CliOutputChecks, simulate_refuses_a_folder_or_unknown_extension_before_simulating) {
  auto d = temp_dir("sim_out");
  CliRun r = run_cli("simulate " + q(kData / "example_model.json") + " --json " + q(d), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.err, "is a folder")) << r.err;
  EXPECT_FALSE(has(r.err, "simulate: ")) << "refused only after work:\n" << r.err;
  r = run_cli("simulate " + q(kData / "example_model.json") + " --plot " + q(d / "out.jpg"), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.err, "'.jpg'")) << r.err;
  EXPECT_FALSE(fs::exists(d / "out.jpg"));
}

TEST(CliOutputChecks, simulate_says_where_it_wrote_and_how_long_it_took) {
  auto d = temp_dir("sim_ok");
  const CliRun r = run_cli("simulate " + q(kData / "example_model.json") + " --json " + q(d / "r.json"), d);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(has(r.out, "wrote " + (d / "r.json").string())) << r.out;
  EXPECT_TRUE(has(r.out, "done in")) << r.out;
}

TEST(CliOutputChecks, decimate_refuses_an_unknown_extension_before_decimating) {
  auto d = temp_dir("dec_ext");
  const CliRun r = run_cli("decimate " + q(kData / "example_model.json") + " --ratio 0.5 -o " + q(d / "d.txt"), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.err, "'.txt'")) << r.err;
}

TEST(CliOutputChecks, decimate_refuses_area_restoration_without_a_projected_area_cap) {
  auto d = temp_dir("dec_restore");
  const CliRun r = run_cli("decimate " + q(kData / "example_model.json") + " --ratio 0.5 --restore-areas -o " +
                               q(d / "d.obj"), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.err, "--projected-area-cap")) << r.err;
  EXPECT_FALSE(std::filesystem::exists(d / "d.obj"));
}

TEST(CliOutputChecks, decimate_never_overwrites_its_node_ratios_file) {
  auto d = temp_dir("dec_ratios");
  write_text(d / "r.json", "{\"body_px\": 0.5}");
  const std::string before = read_text(d / "r.json");
  const CliRun r = run_cli("decimate " + q(kData / "example_model.json") + " --node-ratios " + q(d / "r.json") +
                               " -o " + q(d / "r.json"), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.err, "input")) << r.err;
  EXPECT_EQ(read_text(d / "r.json"), before);
}

TEST(CliOutputChecks, reduce_refuses_a_file_or_foreign_folder_and_its_case_file_before_work) {
  auto d = temp_dir("red_out");
  write_text(d / "afile", "x");
  CliRun r = run_cli("reduce " + q(kData / "example_model.json") + " --out " + q(d / "afile"), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.err, "is not a folder")) << r.err;
  fs::create_directories(d / "foreign");
  write_text(d / "foreign" / "notes.txt", "mine");
  r = run_cli("reduce " + q(kData / "example_model.json") + " --out " + q(d / "foreign"), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.err, "notes.txt")) << r.err;
  fs::create_directories(d / "prev");
  write_text(d / "prev" / "report.json", "{\"environment\": {\"type\": \"fixed_sun\"}}");
  const std::string before = read_text(d / "prev" / "report.json");
  r = run_cli("reduce " + q(kData / "example_model.json") + " --case " + q(d / "prev" / "report.json") + " --out " +
                  q(d / "prev"), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(read_text(d / "prev" / "report.json"), before);
}

TEST(CliCompare, per_node_table_and_tolerance_exit_code_3_when_exceeded) {
  auto d = temp_dir("compare");
  write_text(d / "a.json", R"({"nodes": ["dish", "bus"], "times_s": [0, 10],
    "temperatures_K": {"dish": [300, 301], "bus": [280, 280]}})");
  write_text(d / "b.json", R"({"nodes": ["bus", "dish"], "times_s": [0, 10],
    "temperatures_K": {"dish": [300, 301.5], "bus": [280.1, 280]}})");
  CliRun r = run_cli("compare " + q(d / "a.json") + " " + q(d / "b.json"), d);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(has(r.out, "dish")) << r.out;
  EXPECT_TRUE(has(r.out, "bus")) << r.out;
  r = run_cli("compare " + q(d / "a.json") + " " + q(d / "b.json") + " --tolerance 1", d);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_TRUE(has(r.out, "within tolerance")) << r.out;
  r = run_cli("compare " + q(d / "a.json") + " " + q(d / "b.json") + " --tolerance 0.2", d);
  EXPECT_EQ(r.exit_code, 3) << r.out << r.err;
  EXPECT_TRUE(has(r.out, "EXCEEDS")) << r.out;
}

TEST(CliCompare, a_file_that_is_not_a_result_is_named_in_words) {
  auto d = temp_dir("compare_bad");
  write_text(d / "vf.json", R"({"nodes": ["a"], "view_factors": [[0]]})");
  const CliRun r = run_cli("compare " + q(d / "vf.json") + " " + q(d / "vf.json"), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.err, "not a simulation result")) << r.err;
  EXPECT_FALSE(has(r.err, "json.exception")) << r.err;
}

TEST(CliCommands, unknown_command_is_named_with_the_list_of_commands) {
  auto d = temp_dir("frob");
  const CliRun r = run_cli("frobnicate", d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.err, "unknown command 'frobnicate'")) << r.err;
  EXPECT_TRUE(has(r.err, "simulate")) << r.err;
}

TEST(CliInfo, says_which_environment_and_analysis_the_model_uses) {
  auto d = temp_dir("info_env");
  const CliRun r = run_cli("info " + q(kData / "example_model.json") + " --json " + q(d / "i.json"), d);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(has(r.out, "fixed_sun")) << r.out;
  EXPECT_TRUE(has(r.out, "steady")) << r.out;
  const std::string j = read_text(d / "i.json");
  EXPECT_TRUE(has(j, "\"environment\"")) << j;
  EXPECT_TRUE(has(j, "\"schema_version\"")) << j;
  EXPECT_TRUE(has(j, "\"thermodec_version\"")) << j;
}

TEST(CliSimulate, result_json_carries_versions_and_environment) {
  auto d = temp_dir("sim_versions");
  const CliRun r = run_cli("simulate " + q(kData / "example_model.json") + " --json " + q(d / "r.json"), d);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string j = read_text(d / "r.json");
  for (const char* key : {"\"schema_version\"", "\"thermodec_version\"", "\"environment\"", "\"model\""})
    EXPECT_TRUE(has(j, key)) << key;
}

TEST(CliOutputChecks, reduce_clears_its_earlier_outputs_and_records_version_and_input) {
  auto d = temp_dir("red_again");
  fs::create_directories(d / "out");
  write_text(d / "out" / "mesh.png", "stale picture of an earlier run");
  const CliRun r = run_cli("reduce " + q(kData / "example_model.json") +
                               " --prediction-targets 0.5,1 --no-plots --quiet --out " + q(d / "out"), d);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(fs::exists(d / "out" / "mesh.png")) << "a stale plot stayed beside the new model";
  const std::string report = read_text(d / "out" / "report.json");
  EXPECT_TRUE(has(report, "\"thermodec_version\"")) << report.substr(0, 300);
  EXPECT_TRUE(has(report, "\"schema_version\""));
  EXPECT_TRUE(has(report, "example_model.json"));
  // The predicted-vs-real points asked for, and no others.
  std::size_t points = 0;
  for (std::size_t at = report.find("\"target_K\""); at != std::string::npos; at = report.find("\"target_K\"", at + 1))
    ++points;
  EXPECT_EQ(points, 2u);
  const CliRun bad = run_cli("reduce " + q(kData / "example_model.json") + " --prediction-targets 0,1 --out " +
                             q(d / "bad"), d);
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_FALSE(fs::exists(d / "bad"));
}

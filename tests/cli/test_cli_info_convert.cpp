// The CLI's contract for `info` and `convert`: exit 0 on success, 1 on bad input with a
// one-line reason on stderr, outputs never overwrite inputs.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "thermodec/mesh/io.h"

#include "common/cli_run.h"

namespace fs = std::filesystem;

namespace {

using namespace thermodec::test;

const fs::path kData = THERMODEC_TEST_DATA_DIR;

int lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

}  // namespace

TEST(CliInfo, example_model_prints_counts_and_nodes) {
  auto d = temp_dir("info_ok");
  const CliRun r = run_cli("info " + q(kData / "example_model.json") + " --json " + q(d / "info.json"), d);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("faces               12"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("radiator"), std::string::npos) << r.out;
  const auto j = nlohmann::json::parse(read_text(d / "info.json"));
  EXPECT_EQ(j["faces"], 12);
  EXPECT_EQ(j["components"], 1);
  EXPECT_EQ(j["boundary_edges"], 0);
  EXPECT_EQ(j["nodes"][0]["name"], "body_px");
  EXPECT_EQ(j["nodes"][0]["faces"], 10);
  EXPECT_DOUBLE_EQ(j["nodes"][0]["area_m2"].get<double>(), 5.0);
  EXPECT_EQ(j["nodes"][1]["materials"][0], "white_paint");
}

TEST(CliInfo, bad_mesh_exits_1_with_one_line_naming_file_and_line) {
  auto d = temp_dir("info_bad");
  std::ofstream(d / "bad.obj") << "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n";
  const CliRun r = run_cli("info " + q(d / "bad.obj"), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("bad.obj:2:"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST(CliInfo, missing_file_and_bad_model_key_exit_1_with_one_line) {
  auto d = temp_dir("info_missing");
  CliRun r = run_cli("info " + q(d / "nope.obj"), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(lines(r.err), 1) << r.err;
  fs::copy_file(kData / "satellite.obj", d / "satellite.obj");
  std::ofstream(d / "m.json") << R"({"mesh": "satellite.obj", "nodes": {"antenna": {"power": 1}}})";
  r = run_cli("info " + q(d / "m.json"), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("nodes.antenna"), std::string::npos) << r.err;
}

TEST(CliInfo, json_output_never_overwrites_the_model) {
  auto d = temp_dir("info_protect");
  fs::copy_file(kData / "satellite.obj", d / "satellite.obj");
  const std::string before = read_text(d / "satellite.obj");
  const CliRun r = run_cli("info " + q(d / "satellite.obj") + " --json " + q(d / "satellite.obj"), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(read_text(d / "satellite.obj"), before);
}

TEST(CliInfo, help_exits_0) {
  auto d = temp_dir("info_help");
  const CliRun r = run_cli("info --help", d);
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("MODEL"), std::string::npos);
}

TEST(CliConvert, obj_to_ply_to_obj_keeps_groups_and_materials) {
  auto d = temp_dir("convert_rt");
  CliRun r = run_cli("convert " + q(kData / "satellite.obj") + " " + q(d / "a.ply"), d);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_cli("convert " + q(d / "a.ply") + " " + q(d / "b.obj"), d);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const thermodec::Mesh a = thermodec::read_mesh(kData / "satellite.obj"), b = thermodec::read_mesh(d / "b.obj");
  EXPECT_EQ(a.F, b.F);
  EXPECT_EQ(a.V, b.V);
  EXPECT_EQ(a.node_names, b.node_names);
  EXPECT_EQ(a.face_node, b.face_node);
  EXPECT_EQ(a.material_names, b.material_names);
  EXPECT_EQ(a.face_material, b.face_material);
}

TEST(CliConvert, refuses_to_overwrite_its_input) {
  auto d = temp_dir("convert_self");
  fs::copy_file(kData / "satellite.obj", d / "in.obj");
  const std::string before = read_text(d / "in.obj");
  const CliRun r = run_cli("convert " + q(d / "in.obj") + " " + q(d / "." / "in.obj"), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("overwrite"), std::string::npos) << r.err;
  EXPECT_EQ(read_text(d / "in.obj"), before);
}

TEST(CliConvert, unknown_output_format_exits_1) {
  auto d = temp_dir("convert_ext");
  const CliRun r = run_cli("convert " + q(kData / "satellite.obj") + " " + q(d / "out.dae"), d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("unknown mesh format"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "out.dae"));
}

TEST(CliInfo, usage_errors_exit_1_with_one_line) {
  auto d = temp_dir("usage");
  for (const char* args : {"info", "convert only_one.obj", "info a.obj b.obj", "info --no-such-flag x.obj"}) {
    const CliRun r = run_cli(args, d);
    EXPECT_EQ(r.exit_code, 1) << args;
    EXPECT_EQ(lines(r.err), 1) << args << ": " << r.err;
  }
}

TEST(SharedModelsCliInfo, info_succeeds_on_every_sample_and_nasa_model) {
  auto d = temp_dir("info_all");
  std::vector<fs::path> models;
  const fs::path samples = fs::path(THERMODEC_SOURCE_DIR) / "sample_models";
  const fs::path nasa = fs::path(THERMODEC_SHARED_DIR) / "models" / "nasa";
  for (const fs::path& dir : {samples, nasa}) {
    if (!fs::exists(dir)) continue;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
      const std::string ext = e.path().extension().string();
      if (e.path().parent_path().filename() == "cases") continue;  // load case files, not models
      if (ext == ".json" || ext == ".obj" || ext == ".ply" || ext == ".stl") models.push_back(e.path());
    }
  }
  if (models.empty()) GTEST_SKIP() << "no sample or NASA models found";
  // A load case file given as a model: exit 1 with a message that says what it is.
  const fs::path case_file = samples / "satellite" / "cases" / "december.json";
  if (fs::exists(case_file)) {
    const CliRun r = run_cli("info " + q(case_file), d);
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.err.find("--case"), std::string::npos) << r.err;
  }
  std::sort(models.begin(), models.end());
  for (const auto& m : models) {
    const CliRun r = run_cli("info " + q(m), d);
    EXPECT_EQ(r.exit_code, 0) << m << ": " << r.err;
    EXPECT_NE(r.out.find("nodes "), std::string::npos) << m;
  }
}

TEST(CliInfo, bare_mesh_with_a_sheet_inside_a_closed_box_reports_the_enclosed_faces) {
  auto d = temp_dir("info_enclosed");
  // A 3 m cube (outward) around a 1 m square sheet: the cube's 12 faces radiate from both sides.
  const double c[8][3] = {{0, 0, 0}, {3, 0, 0}, {3, 3, 0}, {0, 3, 0}, {0, 0, 3}, {3, 0, 3}, {3, 3, 3}, {0, 3, 3}};
  const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
  std::ostringstream stl;
  auto tri = [&](const double* a, const double* b, const double* e) {
    stl << "facet normal 0 0 0\nouter loop\n";
    for (const double* v : {a, b, e}) stl << "vertex " << v[0] << " " << v[1] << " " << v[2] << "\n";
    stl << "endloop\nendfacet\n";
  };
  stl << "solid enclosed\n";
  for (const auto& q4 : quads) tri(c[q4[0]], c[q4[1]], c[q4[2]]), tri(c[q4[0]], c[q4[2]], c[q4[3]]);
  const double s[4][3] = {{1, 1, 1.5}, {2, 1, 1.5}, {2, 2, 1.5}, {1, 2, 1.5}};
  tri(s[0], s[1], s[2]), tri(s[0], s[2], s[3]);
  stl << "endsolid enclosed\n";
  std::ofstream(d / "enclosed.stl") << stl.str();
  const CliRun r = run_cli("info " + q(d / "enclosed.stl") + " --json " + q(d / "info.json"), d);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("enclosed faces      2 inside 1 closed parts, whose 12 faces radiate from both sides"),
            std::string::npos)
      << r.out;
  const auto j = nlohmann::json::parse(read_text(d / "info.json"));
  EXPECT_EQ(j["enclosed"]["faces"], 2);
  EXPECT_EQ(j["enclosed"]["closed_parts"], 1);
  EXPECT_EQ(j["enclosed"]["shell_faces_made_two_sided"], 12);
}

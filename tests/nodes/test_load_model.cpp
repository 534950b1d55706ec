#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/scratch_dir.h"
#include "thermodec/common/errors.h"
#include "thermodec/mesh/io.h"
#include "thermodec/mesh/mesh_stats.h"
#include "thermodec/nodes/load_case.h"
#include "thermodec/nodes/load_model.h"

namespace fs = std::filesystem;
using namespace thermodec;
using json = nlohmann::ordered_json;

namespace {

const fs::path kData = THERMODEC_TEST_DATA_DIR;

fs::path temp_dir(const std::string& name) { return thermodec::test::scratch_dir("thermodec_test_model", name); }

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

json example() { return json::parse(read_text(kData / "example_model.json")); }

// Writes `model` beside a copy of the example mesh and loads it.
ThermalModel load_variant(const json& model, const std::string& name = "variant") {
  const fs::path d = temp_dir(name);
  fs::copy_file(kData / "satellite.obj", d / "satellite.obj");
  std::ofstream(d / "model.json") << model.dump(2);
  return load_model(d / "model.json");
}

// The variant must be rejected with a one-line InvalidInput naming `key` (and `also`).
void expect_rejected(const json& model, const std::string& key, const std::string& also = "") {
  try {
    load_variant(model, "rejected");
    ADD_FAILURE() << "accepted a model with a bad '" << key << "'";
  } catch (const InvalidInput& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(key), std::string::npos) << "'" << key << "' not named in: " << msg;
    EXPECT_NE(msg.find(also), std::string::npos) << "'" << also << "' not in: " << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
}

}  // namespace

TEST(LoadModel, worked_example_loads_as_written) {
  const ThermalModel m = load_model(kData / "example_model.json");
  ASSERT_EQ(m.nodes.size(), 2u);
  EXPECT_EQ(m.nodes[0].name, "body_px");
  EXPECT_EQ(m.nodes[0].capacitance_J_per_K, 2000.0);
  EXPECT_EQ(m.nodes[0].power_W, 5.0);
  EXPECT_FALSE(m.nodes[0].fixed_temperature_K.has_value());
  EXPECT_EQ(m.nodes[1].name, "radiator");
  EXPECT_EQ(m.nodes[1].fixed_temperature_K.value(), 290.0);
  ASSERT_EQ(m.materials.size(), 1u);
  EXPECT_EQ(m.materials[0].name, "white_paint");
  EXPECT_EQ(m.materials[0].absorptivity, 0.20);
  EXPECT_EQ(m.materials[0].emissivity, 0.85);
  ASSERT_EQ(m.conductances.size(), 1u);
  EXPECT_EQ(m.conductances[0].from, 0);
  EXPECT_EQ(m.conductances[0].to, 1);
  EXPECT_EQ(m.conductances[0].conductance_W_per_K, 0.8);
  EXPECT_EQ(m.environment.type, EnvironmentType::fixed_sun);
  EXPECT_EQ(m.environment.sun_direction, Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(m.environment.solar_flux_W_per_m2, 1361.0);
  EXPECT_EQ(m.analysis.type, AnalysisType::steady);
  EXPECT_EQ(m.radiation.rays_per_face, 4000);
  EXPECT_EQ(m.radiation.seed, 1u);
  // Mesh: a closed 1 m cube, five sides body_px, the top radiator, all faces resolved.
  EXPECT_EQ(m.mesh.num_faces(), 12);
  EXPECT_EQ(m.mesh.node_names, (std::vector<std::string>{"body_px", "radiator"}));
  EXPECT_EQ(m.mesh.material_names, (std::vector<std::string>{"white_paint"}));
  EXPECT_EQ(node_areas_m2(m.mesh), (std::vector<double>{5.0, 1.0}));
  EXPECT_EQ(m.mesh.face_material, Eigen::VectorXi::Zero(12));
  EXPECT_EQ(m.mesh.face_back_material, Eigen::VectorXi::Constant(12, -1));
  EXPECT_EQ(m.mesh_path, kData / "satellite.obj");
}

TEST(LoadModel, docs_example_is_the_tested_example_file) {
  const std::string doc = read_text(fs::path(THERMODEC_SOURCE_DIR) / "docs" / "model-format.md");
  const auto start = doc.find("```json\n");
  ASSERT_NE(start, std::string::npos);
  const auto end = doc.find("```", start + 8);
  EXPECT_EQ(json::parse(doc.substr(start + 8, end - start - 8)), example());
}

TEST(LoadModel, bare_mesh_is_a_model_with_documented_defaults) {
  const ThermalModel m = load_model(kData / "satellite.obj");
  EXPECT_EQ(m.nodes.size(), 2u);
  EXPECT_EQ(m.nodes[1].capacitance_J_per_K, 0.0);
  // "default" first, then the mesh's usemtl names, all with the default coating.
  ASSERT_EQ(m.materials.size(), 2u);
  EXPECT_EQ(m.materials[0].name, "default");
  EXPECT_EQ(m.materials[1].name, "white_paint");
  for (const auto& mat : m.materials) {
    EXPECT_EQ(mat.absorptivity, 0.5);
    EXPECT_EQ(mat.emissivity, 0.8);
  }
  EXPECT_EQ(m.default_material, 0);
  EXPECT_EQ(m.environment.type, EnvironmentType::orbit);
  EXPECT_EQ(m.environment.altitude_km, 500.0);
  EXPECT_EQ(m.analysis.type, AnalysisType::steady);
  EXPECT_EQ(m.radiation.rays_per_face, 4000);
  EXPECT_EQ(m.mesh.face_material, Eigen::VectorXi::Constant(12, 1));
}

TEST(LoadModel, mesh_without_groups_gets_automatic_nodes_on_every_face) {
  const fs::path d = temp_dir("auto");
  Mesh cube = load_model(kData / "satellite.obj").mesh;
  cube.node_names.clear();
  cube.face_node.setConstant(-1);
  write_mesh(d / "cube.stl", cube);
  const ThermalModel m = load_model(d / "cube.stl");
  EXPECT_EQ(m.nodes.size(), 6u);  // one per flat side
  EXPECT_GE(m.mesh.face_node.minCoeff(), 0);
  EXPECT_EQ(m.mesh.node_names.size(), m.nodes.size());
  EXPECT_EQ(m.mesh.face_material, Eigen::VectorXi::Zero(12));
}

// A raw CAD export wrapped in a model file is loaded as it is given bare: cleaned (the open
// panel made two-sided) before its automatic nodes are built, so it reduces the same way.
TEST(LoadModel, raw_mesh_in_a_model_file_is_cleaned_as_when_given_bare) {
  const fs::path d = temp_dir("raw_in_model");
  Mesh m = load_model(kData / "satellite.obj").mesh;  // a closed cube
  m.node_names.clear();
  m.face_node.setConstant(-1);
  m.face_material.setConstant(-1);
  m.face_back_material.setConstant(-1);
  const int nv = m.num_vertices(), nf = m.num_faces();
  m.V.conservativeResize(nv + 3, 3);  // an open one-sided triangle beside it
  m.V.row(nv) << 3, 0, 0;
  m.V.row(nv + 1) << 4, 0, 0;
  m.V.row(nv + 2) << 3, 1, 0;
  m.F.conservativeResize(nf + 1, 3);
  m.F.row(nf) << nv, nv + 1, nv + 2;
  for (Eigen::VectorXi* a : {&m.face_node, &m.face_material, &m.face_back_material}) {
    a->conservativeResize(nf + 1);
    (*a)[nf] = -1;
  }
  write_mesh(d / "part.stl", m);
  const ThermalModel bare = load_model(d / "part.stl");
  std::ofstream(d / "model.json") << json({{"mesh", "part.stl"}}).dump();
  const ThermalModel wrapped = load_model(d / "model.json");
  ASSERT_TRUE(bare.mesh_cleanup.has_value());
  ASSERT_TRUE(wrapped.mesh_cleanup.has_value());
  EXPECT_EQ(wrapped.mesh_cleanup->open_sheet_faces_made_two_sided, 1);
  EXPECT_EQ(wrapped.mesh.V, bare.mesh.V);
  EXPECT_EQ(wrapped.mesh.F, bare.mesh.F);
  EXPECT_EQ(wrapped.mesh.face_node, bare.mesh.face_node);
  EXPECT_EQ(wrapped.mesh.face_back_material, bare.mesh.face_back_material);
  EXPECT_EQ(wrapped.nodes.size(), bare.nodes.size());
  // A model file that sets its own sampling keeps the mesh as written.
  std::ofstream(d / "model.json") << json({{"mesh", "part.stl"}, {"radiation", {{"rays_per_face", 500}}}}).dump();
  const ThermalModel own = load_model(d / "model.json");
  EXPECT_FALSE(own.mesh_cleanup.has_value());
  EXPECT_EQ(own.mesh.face_back_material.maxCoeff(), -1);
}

TEST(LoadModel, usemtl_overrides_node_material_and_unlisted_groups_get_defaults) {
  const fs::path d = temp_dir("override");
  std::ofstream(d / "m.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                                "f 1 2 3\n"                      // before any group
                                "g panel\nf 2 4 3\nusemtl osr\nf 1 2 4\n"
                                "g spare\nusemtl\nf 1 4 3\n";
  json j = {{"mesh", "m.obj"},
            {"materials", {{"paint", {{"absorptivity", 0.3}, {"emissivity", 0.9}}},
                           {"osr", {{"absorptivity", 0.1}, {"emissivity", 0.8}}}}},
            {"default_material", "paint"},
            {"nodes", {{"panel", {{"material", "paint"}, {"capacitance", 10.0}}}}}};
  std::ofstream(d / "m.json") << j.dump();
  const ThermalModel m = load_model(d / "m.json");
  EXPECT_EQ(m.mesh.node_names, (std::vector<std::string>{"panel", "spare", "ungrouped"}));
  EXPECT_EQ(m.mesh.face_node, Eigen::Vector4i(2, 0, 0, 1));
  EXPECT_EQ(m.mesh.face_material, Eigen::Vector4i(0, 0, 1, 0));  // usemtl osr wins inside panel
  EXPECT_EQ(m.nodes[1].capacitance_J_per_K, 0.0);
  EXPECT_EQ(m.nodes[1].material, -1);
}

TEST(LoadModel, two_sided_nodes_get_their_back_material) {
  json j = example();
  j["materials"]["mli"] = {{"absorptivity", 0.4}, {"emissivity", 0.7}};
  j["nodes"]["radiator"]["back_material"] = "mli";
  j["nodes"]["body_px"]["two_sided"] = true;
  const ThermalModel m = load_variant(j);
  for (int f = 0; f < 12; ++f) {
    const bool radiator = m.mesh.face_node[f] == 1;
    EXPECT_EQ(m.mesh.face_back_material[f], radiator ? 1 : 0) << f;  // body_px: back = its front
  }
}

TEST(LoadModel, unit_scale_converts_mesh_to_metres) {
  json j = example();
  j["unit_scale"] = 0.001;
  const ThermalModel m = load_variant(j);
  EXPECT_DOUBLE_EQ(m.mesh.V.maxCoeff(), 0.001);
  EXPECT_EQ(m.unit_scale, 0.001);
}

TEST(LoadModelErrors, unknown_names_are_rejected_naming_the_key) {
  json j = example();
  j["nodes"]["antenna"] = {{"power", 1.0}};
  expect_rejected(j, "nodes.antenna", "no group named 'antenna'");
  j = example();
  j["nodes"]["body_px"]["material"] = "gold";
  expect_rejected(j, "nodes.body_px.material", "gold");
  j = example();
  j["default_material"] = "gold";
  expect_rejected(j, "default_material", "gold");
  j = example();
  j["conductances"][0]["to"] = "antenna";
  expect_rejected(j, "conductances[0].to", "antenna");
  j = example();
  j["nodes"]["body_px"]["capacitence"] = 3.0;
  expect_rejected(j, "nodes.body_px.capacitence", "unknown key");
  j = example();
  j["materials"] = {{"black", {{"absorptivity", 0.9}, {"emissivity", 0.9}}}};
  j["default_material"] = "black";
  j["nodes"]["body_px"].erase("material");
  expect_rejected(j, "white_paint", "not defined in the model's 'materials'");  // the mesh's usemtl
}

TEST(LoadModelErrors, out_of_range_values_are_rejected_naming_the_key) {
  struct Case { const char* pointer; json value; const char* key; };
  const Case cases[] = {
      {"/materials/white_paint/absorptivity", 0.0, "materials.white_paint.absorptivity"},
      {"/materials/white_paint/absorptivity", 1.2, "materials.white_paint.absorptivity"},
      {"/materials/white_paint/emissivity", -0.1, "materials.white_paint.emissivity"},
      {"/materials/white_paint/emissivity", "high", "materials.white_paint.emissivity"},
      {"/nodes/body_px/capacitance", -1.0, "nodes.body_px.capacitance"},
      {"/nodes/radiator/fixed_temperature", -3.0, "nodes.radiator.fixed_temperature"},
      {"/conductances/0/value", -0.5, "conductances[0].value"},
      {"/unit_scale", 0.0, "unit_scale"},
      {"/environment/type", "deep_space", "environment.type"},
      {"/environment/solar_flux", -1.0, "environment.solar_flux"},
      {"/environment/sun_direction", json::array({0, 0, 0}), "environment.sun_direction"},
      {"/environment/altitude_km", 500.0, "environment.altitude_km"},  // not a fixed_sun key
      {"/analysis/type", "transient", "analysis.type"},
      {"/analysis/orbits", 3, "analysis.orbits"},  // not a steady key
      {"/radiation/rays_per_face", 0, "radiation.rays_per_face"},
      {"/radiation/rays_per_face", 4000.5, "radiation.rays_per_face"},
      {"/radiation/seed", -1, "radiation.seed"},
      {"/mesh", "satellite.dae", "mesh"},
  };
  for (const auto& c : cases) {
    json j = example();
    j[json::json_pointer(c.pointer)] = c.value;
    SCOPED_TRACE(c.pointer);
    expect_rejected(j, c.key);
  }
}

TEST(LoadModelErrors, orbit_environment_and_transient_analysis_are_validated) {
  json j = example();
  j["environment"] = {{"type", "orbit"}, {"altitude_km", 700.0}, {"inclination_deg", 98.0}, {"raan_deg", 90.0},
                      {"day_of_year", 172}, {"attitude", "sun"}, {"albedo", 0.3}, {"earth_ir_flux", 237.0}};
  j["analysis"] = {{"type", "transient_orbit"}, {"steps_per_orbit", 60}, {"orbits", 2}};
  const ThermalModel m = load_variant(j);
  EXPECT_EQ(m.environment.type, EnvironmentType::orbit);
  EXPECT_EQ(m.environment.attitude, Attitude::sun);
  EXPECT_EQ(m.environment.day_of_year, 172);
  EXPECT_EQ(m.analysis.steps_per_orbit, 60);
  EXPECT_EQ(m.analysis.orbits, 2);
  json bad = j;
  bad["environment"]["attitude"] = "tumbling";
  expect_rejected(bad, "environment.attitude", "tumbling");
  bad = j;
  bad["environment"]["day_of_year"] = 367;
  expect_rejected(bad, "environment.day_of_year");
  bad = j;
  bad["environment"]["albedo"] = 1.5;
  expect_rejected(bad, "environment.albedo");
  bad = j;
  bad["environment"]["inclination_deg"] = -10;
  expect_rejected(bad, "environment.inclination_deg");
  bad = j;
  bad["analysis"]["steps_per_orbit"] = 0;
  expect_rejected(bad, "analysis.steps_per_orbit");
  bad = example();
  bad["analysis"] = {{"type", "transient_orbit"}};
  expect_rejected(bad, "analysis.type", "orbit");  // fixed_sun has no orbit period
}

TEST(LoadModelErrors, structural_problems_are_rejected) {
  json j = example();
  j["conductances"][0]["to"] = "body_px";
  expect_rejected(j, "conductances[0]", "itself");
  j = example();
  j["conductances"] = {{"from", "body_px"}};
  expect_rejected(j, "conductances");
  j = example();
  j.erase("mesh");
  expect_rejected(j, "mesh", "missing");
  j = example();
  j["materials"]["white_paint"].erase("emissivity");
  expect_rejected(j, "materials.white_paint", "emissivity");
  j = example();
  j["environment"].erase("type");
  expect_rejected(j, "environment", "type");
  j = example();
  j["nodes"]["radiator"]["two_sided"] = false;
  j["nodes"]["radiator"]["back_material"] = "white_paint";
  expect_rejected(j, "nodes.radiator.back_material");
}

TEST(LoadModelErrors, bad_files_name_the_file) {
  const fs::path d = temp_dir("badfiles");
  std::ofstream(d / "syntax.json") << "{\n  \"mesh\": \"satellite.obj\",\n  \"unit_scale\": ,\n}\n";
  try {
    load_model(d / "syntax.json");
    ADD_FAILURE();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("syntax.json"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("line 3"), std::string::npos) << e.what();
  }
  std::ofstream(d / "inf.json") << R"({"mesh": "satellite.obj", "unit_scale": 1e999})";
  try {
    load_model(d / "inf.json");
    ADD_FAILURE();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("inf.json"), std::string::npos) << e.what();
  }
  std::ofstream(d / "nan.json") << "{\"mesh\": \"satellite.obj\",\n \"unit_scale\": NaN}";
  try {
    load_model(d / "nan.json");
    ADD_FAILURE();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("line 2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(load_model(d / "missing.json"), IOError);
  std::ofstream(d / "nomesh.json") << R"({"mesh": "absent.obj"})";
  EXPECT_THROW(load_model(d / "nomesh.json"), IOError);
  std::ofstream(d / "array.json") << "[1, 2]";
  EXPECT_THROW(load_model(d / "array.json"), InvalidInput);
  std::ofstream(d / "model.txt") << "{}";
  EXPECT_THROW(load_model(d / "model.txt"), InvalidInput);
}

TEST(SaveModel, round_trip_through_obj_and_ply_keeps_everything) {
  json j = example();
  j["materials"]["mli"] = {{"absorptivity", 0.4}, {"emissivity", 0.7}};
  j["nodes"]["radiator"]["back_material"] = "mli";
  j["environment"] = {{"type", "orbit"}, {"altitude_km", 650.0}, {"attitude", "inertial"}};
  j["analysis"] = {{"type", "transient_orbit"}, {"steps_per_orbit", 36}};
  j["radiation"]["seed"] = 18446744073709551615ull;
  const ThermalModel a = load_variant(j, "save_src");
  for (const char* mesh_name : {"mesh/out.obj", "mesh/out.ply"}) {
    const fs::path d = temp_dir("save_dst");
    save_model(a, d / "out.json", d / mesh_name);
    const ThermalModel b = load_model(d / "out.json");
    SCOPED_TRACE(mesh_name);
    EXPECT_EQ(b.mesh.V, a.mesh.V);
    EXPECT_EQ(b.mesh.F, a.mesh.F);
    EXPECT_EQ(b.mesh.face_node, a.mesh.face_node);
    EXPECT_EQ(b.mesh.face_material, a.mesh.face_material);
    EXPECT_EQ(b.mesh.face_back_material, a.mesh.face_back_material);
    EXPECT_EQ(b.mesh.node_names, a.mesh.node_names);
    ASSERT_EQ(b.nodes.size(), a.nodes.size());
    for (std::size_t n = 0; n < a.nodes.size(); ++n) {
      EXPECT_EQ(b.nodes[n].capacitance_J_per_K, a.nodes[n].capacitance_J_per_K);
      EXPECT_EQ(b.nodes[n].power_W, a.nodes[n].power_W);
      EXPECT_EQ(b.nodes[n].fixed_temperature_K, a.nodes[n].fixed_temperature_K);
    }
    EXPECT_EQ(b.conductances.size(), 1u);
    EXPECT_EQ(b.environment.altitude_km, 650.0);
    EXPECT_EQ(b.environment.attitude, Attitude::inertial);
    EXPECT_EQ(b.analysis.steps_per_orbit, 36);
    EXPECT_EQ(b.radiation.seed, 18446744073709551615ull);
    EXPECT_EQ(json::parse(read_text(d / "out.json"))["mesh"], mesh_name);
  }
  EXPECT_THROW(save_model(a, temp_dir("save_stl") / "x.json", temp_dir("save_stl") / "x.stl"), InvalidInput);
}

TEST(LoadModel, sample_satellite_model_loads) {
  const fs::path p = fs::path(THERMODEC_SOURCE_DIR) / "sample_models" / "satellite" / "model.json";
  if (!fs::exists(p)) GTEST_SKIP() << p << " not present";
  const ThermalModel m = load_model(p);
  EXPECT_EQ(m.nodes.size(), m.mesh.node_names.size());
  EXPECT_GE(m.mesh.face_node.minCoeff(), 0);
  EXPECT_GE(m.mesh.face_material.minCoeff(), 0);
  EXPECT_EQ(m.environment.type, EnvironmentType::orbit);
}

TEST(LoadModel, sun_direction_with_extreme_components_keeps_its_direction) {
  // Found by the reader fuzzer: the plain norm of [1, 0, -1e308] overflows, which made the
  // direction the zero vector, and that of [1e-200, 0, 0] underflows, which refused it.
  json j = example();
  j["environment"]["sun_direction"] = json::array({1, 0, -1e308});
  EXPECT_TRUE(load_variant(j).environment.sun_direction.isApprox(Eigen::Vector3d(0, 0, -1)));
  j["environment"]["sun_direction"] = json::array({1e-200, 0, 0});
  EXPECT_EQ(load_variant(j).environment.sun_direction, Eigen::Vector3d(1, 0, 0));
}

TEST(LoadModel, power_schedule_and_heater_load_save_and_load_again) {
  json j = example();
  j["environment"] = {{"type", "orbit"}};
  j["analysis"] = {{"type", "transient_orbit"}};
  const std::string a = "body_px", b = a;  // capacitance 2000 J/K
  j["nodes"][a].erase("power");
  j["nodes"][a]["power_schedule_W"] = {{0.0, 5.0}, {1200.0, 40.0}};
  j["nodes"][b]["heater"] = {{"on_K", 270.0}, {"off_K", 275.0}, {"power_W", 12.0}};
  const ThermalModel m = load_variant(j);
  const auto node = [&](const ThermalModel& model, const std::string& name) {
    for (const Node& n : model.nodes)
      if (n.name == name) return n;
    return Node{};
  };
  ASSERT_EQ(node(m, a).power_schedule_W.size(), 2u);
  EXPECT_EQ(node(m, a).power_schedule_W[1], std::make_pair(1200.0, 40.0));
  ASSERT_TRUE(node(m, b).heater.has_value());
  EXPECT_EQ(node(m, b).heater->off_K, 275.0);
  // The reduced model.json of `reduce` is written by save_model: both keys survive it.
  const fs::path d = temp_dir("saved_schedule");
  save_model(m, d / "model.json", d / "mesh.obj");
  const ThermalModel back = load_model(d / "model.json");
  EXPECT_EQ(node(back, a).power_schedule_W, node(m, a).power_schedule_W);
  EXPECT_EQ(node(back, a).power_W, 0.0);
  ASSERT_TRUE(node(back, b).heater.has_value());
  EXPECT_TRUE(*node(back, b).heater == *node(m, b).heater);
}

TEST(LoadModelErrors, power_schedules_and_heaters_are_validated) {
  json j = example();
  j["environment"] = {{"type", "orbit"}};
  j["analysis"] = {{"type", "transient_orbit"}};
  const std::string a = "body_px";
  json bad = j;
  bad["nodes"][a]["power_schedule_W"] = {{0.0, 5.0}};  // beside "power"
  expect_rejected(bad, "nodes." + a, "either");
  bad = j;
  bad["nodes"][a].erase("power");
  bad["nodes"][a]["power_schedule_W"] = {{10.0, 5.0}};
  expect_rejected(bad, "power_schedule_W[0]", "0 s");
  bad["nodes"][a]["power_schedule_W"] = {{0.0, 5.0}, {0.0, 1.0}};
  expect_rejected(bad, "power_schedule_W[1]", "increase");
  bad = j;
  bad["nodes"][a]["capacitance"] = 100.0;
  bad["nodes"][a]["heater"] = {{"on_K", 275.0}, {"off_K", 270.0}, {"power_W", 1.0}};
  expect_rejected(bad, "heater", "below");
  bad["nodes"][a]["heater"] = {{"on_K", 270.0}, {"off_K", 275.0}, {"power_W", 1.0}};
  bad["analysis"] = {{"type", "steady"}};
  expect_rejected(bad, "heater", "transient_orbit");
  bad["analysis"] = {{"type", "transient_orbit"}};
  bad["nodes"][a]["capacitance"] = 0.0;
  expect_rejected(bad, "heater", "capacitance");
}

TEST(LoadModelErrors, a_steady_load_case_on_a_model_with_a_heater_is_refused_before_any_work) {
  json j = example();
  j["environment"] = {{"type", "orbit"}};
  j["analysis"] = {{"type", "transient_orbit"}};
  j["nodes"]["body_px"]["heater"] = {{"on_K", 270.0}, {"off_K", 275.0}, {"power_W", 1.0}};
  const ThermalModel m = load_variant(j);
  LoadCase steady = own_case(m, "cold");
  steady.analysis.type = AnalysisType::steady;
  try {
    with_case(m, steady);
    ADD_FAILURE() << "a steady case with a thermostat was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("load case 'cold'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("transient_orbit"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(with_case(m, own_case(m)));
}

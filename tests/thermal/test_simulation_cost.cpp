// The cost estimate of a simulation (thermal/simulation_cost.h): exact IR ray counts, limits
// that legitimate runs never reach, and refusals that name the setting at fault.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "thermodec/environment/external_loads.h"
#include "thermodec/nodes/load_model.h"
#include "thermodec/radiation/radiative_couplings.h"
#include "thermodec/thermal/simulation_cost.h"

using namespace thermodec;

namespace {

const std::filesystem::path kSource = THERMODEC_SOURCE_DIR;

bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// A flat n x n grid of quads (2 n^2 triangles) in `nodes` strips, on a nadir orbit with an
// orbit transient at the default settings. Built directly: 100 000 faces in milliseconds.
ThermalModel grid_model(int n, int nodes, bool two_sided) {
  ThermalModel m;
  m.materials = {Material{"paint", 0.3, 0.8}};
  m.mesh.material_names = {"paint"};
  for (int k = 0; k < nodes; ++k) {
    Node node;
    node.name = "strip" + std::to_string(k);
    node.material = 0;
    node.capacitance_J_per_K = 1000.0;
    m.nodes.push_back(node);
    m.mesh.node_names.push_back(node.name);
  }
  m.mesh.V.resize((n + 1) * (n + 1), 3);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.mesh.V.row(j * (n + 1) + i) << 0.01 * i, 0.01 * j, 0.0;
  const int faces = 2 * n * n;
  m.mesh.F.resize(faces, 3);
  m.mesh.face_node.resize(faces);
  m.mesh.face_material.setConstant(faces, 0);
  m.mesh.face_back_material.setConstant(faces, two_sided ? 0 : -1);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, f = 2 * (j * n + i);
      m.mesh.F.row(f) << a, a + 1, a + n + 2;
      m.mesh.F.row(f + 1) << a, a + n + 2, a + n + 1;
      m.mesh.face_node[f] = m.mesh.face_node[f + 1] = std::min(nodes - 1, j * nodes / n);
    }
  m.environment.type = EnvironmentType::orbit;
  m.analysis.type = AnalysisType::transient_orbit;
  return m;
}

}  // namespace

TEST(SimulationCost, ir_rays_are_the_rays_the_view_factors_trace) {
  const ThermalModel model = load_model(kSource / "tests/data/example_model.json");
  const SimulationCost cost = simulation_cost(model, {}, SimulationCostScope::view_factors);
  const NodeCouplings c = radiative_couplings(model, model.radiation);
  EXPECT_EQ(cost.ir_rays, double(c.diagnostics.rays_traced));
  // the view-factor rows: at most one entry per ray and per side, 12 bytes each
  EXPECT_LE(cost.view_factor_bytes_max, 12.0 * cost.ir_rays);
  EXPECT_LE(cost.view_factor_bytes_max, 12.0 * double(cost.sides) * cost.sides);
  EXPECT_EQ(cost.sides, c.diagnostics.surface_sides);
  EXPECT_EQ(cost.sun_rays, 0.0);
  EXPECT_EQ(cost.solver_steps, 0.0);
}

TEST(SimulationCost, the_sample_satellite_is_far_below_every_limit) {
  const ThermalModel model = load_model(kSource / "sample_models/satellite/model.json");
  const SimulationCost cost = simulation_cost(model);
  const SimulationCostLimits limits;
  EXPECT_EQ(simulation_cost_excess(cost, model), "");
  EXPECT_LT(cost.rays(), limits.max_rays / 100.0) << cost.summary();
  EXPECT_LT(cost.solver_work, limits.max_solver_work / 100.0) << cost.summary();
  EXPECT_LT(cost.memory_bytes(), limits.max_memory_bytes / 100.0) << cost.summary();
  // Nadir orbit: one shadow pass per sunlit position, each new sun direction in body axes.
  EXPECT_EQ(cost.load_positions, 120);
  EXPECT_GT(cost.shadow_passes, 60);
  EXPECT_LT(cost.shadow_passes, 120);
  // 5 grid levels of 60 x 2 steps sufficed in practice (1936 at the finest) at 60 positions; the
  // bound takes 7 levels of the 120 positions' grid.
  EXPECT_GT(cost.solver_steps, 3 * 1936.0 * 2);
}

TEST(SimulationCost, a_100k_face_model_at_default_settings_is_within_the_limits_even_two_sided) {
  for (bool two_sided : {false, true}) {
    const ThermalModel model = grid_model(224, 64, two_sided);  // 100 352 faces
    ASSERT_GT(model.mesh.num_faces(), 100000);
    const SimulationCost cost = simulation_cost(model);
    EXPECT_EQ(simulation_cost_excess(cost, model), "") << cost.summary();
    EXPECT_GE(cost.ir_rays, 4000.0 * model.mesh.num_faces() * (two_sided ? 2 : 1)) << cost.summary();
    EXPECT_LT(cost.rays(), SimulationCostLimits{}.max_rays / 2.0) << cost.summary();
    // every side's 4096 rays (4000 rounded to a power of two) could hit as many distinct sides:
    // 12 bytes each, shown not guarded
    EXPECT_EQ(cost.view_factor_bytes_max, 12.0 * 4096.0 * cost.sides) << cost.summary();
    EXPECT_NE(cost.summary().find("view-factor rows up to"), std::string::npos) << cost.summary();
  }
}

TEST(SimulationCost, rays_per_face_near_its_maximum_on_a_big_mesh_is_refused_naming_it) {
  ThermalModel model = grid_model(40, 8, false);  // 3200 faces
  model.radiation.rays_per_face = 10000000;
  const std::string why = simulation_cost_excess(simulation_cost(model), model);
  EXPECT_TRUE(has(why, "radiation.rays_per_face = 10000000")) << why;
  EXPECT_TRUE(has(why, "rays to trace")) << why;
  // viewfactors traces the same IR rays.
  EXPECT_TRUE(has(simulation_cost_excess(simulation_cost(model, {}, SimulationCostScope::view_factors), model),
                  "radiation.rays_per_face"));
}

TEST(SimulationCost, a_million_orbit_positions_on_a_12_face_model_is_refused_naming_them) {
  ThermalModel model = load_model(kSource / "tests/data/example_model.json");
  model.environment.type = EnvironmentType::orbit;
  model.analysis.type = AnalysisType::transient_orbit;
  model.analysis.steps_per_orbit = 1000000;
  const SimulationCost cost = simulation_cost(model);
  const std::string why = simulation_cost_excess(cost, model);
  EXPECT_TRUE(has(why, "analysis.steps_per_orbit = 1000000")) << why;
  // The solver alone would be refused too: 3 orbits x 7 levels of 2 x 10^6 steps and more.
  EXPECT_GT(cost.solver_steps, 3.0 * 127.0 * 2e6);
  EXPECT_GT(cost.solver_work, SimulationCostLimits{}.max_solver_work);
  // The override ModelSimulationSettings::loads.steps_per_orbit (`simulate --load-positions`) counts.
  model.analysis.steps_per_orbit = 72;
  EXPECT_EQ(simulation_cost_excess(simulation_cost(model), model), "");
  ModelSimulationSettings settings;
  settings.loads.steps_per_orbit = 1000000;
  EXPECT_TRUE(has(simulation_cost_excess(simulation_cost(model, settings), model, settings), "1000000 load positions"));
}

TEST(SimulationCost, thousands_of_nodes_in_an_orbit_transient_are_refused_for_the_solver) {
  ThermalModel model = grid_model(40, 2000, false);
  model.radiation.min_rays_per_node = 0;
  const SimulationCost cost = simulation_cost(model);
  const std::string why = simulation_cost_excess(cost, model);
  EXPECT_TRUE(has(why, "thermal solver work")) << why;
  EXPECT_TRUE(has(why, "2000 nodes")) << why;
  // Steady: one Newton solve, allowed.
  model.analysis.type = AnalysisType::steady;
  EXPECT_EQ(simulation_cost_excess(simulation_cost(model), model), "");
}

TEST(SimulationCost, a_huge_sampling_boost_is_refused_for_its_rays_and_sample_table) {
  ThermalModel model = load_model(kSource / "tests/data/example_model.json");
  for (Node& n : model.nodes) n.sampling_boost.ir = 1e4;
  model.radiation.rays_per_face = 1000000;
  const SimulationCost cost = simulation_cost(model, {}, SimulationCostScope::view_factors);
  EXPECT_GE(cost.sobol_table_bytes, 16.0 * 1e9);  // rays per side are capped at 1e9
  EXPECT_TRUE(has(simulation_cost_excess(cost, model), "rays to trace"));
  SimulationCostLimits only_memory;  // which part of the memory, when memory is what exceeds
  only_memory.max_rays = 1e300;
  only_memory.max_memory_bytes = 1e9;
  const std::string why = simulation_cost_excess(cost, model, {}, only_memory);
  EXPECT_TRUE(has(why, "memory")) << why;
  EXPECT_TRUE(has(why, "sample table")) << why;
}

TEST(SimulationCost, noise_targeting_adds_its_extra_shadow_samples_at_the_passes_rate_of_the_models_own) {
  // The extra sun samples noise targeting may add are per-side counts, traced as the model's
  // own: at every pass of a transient orbit, at every D-th of a steady one (each pass draws
  // count / D of them). Bound by the cap on extra samples, so only it decides the extra rays.
  ThermalModel model = grid_model(20, 4, false);
  model.analysis.type = AnalysisType::steady;
  const SimulationCost steady = simulation_cost(model);
  model.analysis.type = AnalysisType::transient_orbit;
  const SimulationCost transient = simulation_cost(model);
  ASSERT_GT(steady.shadow_passes, 1);
  EXPECT_EQ(steady.shadow_division, shadow_pass_division(steady.shadow_passes));
  EXPECT_GT(steady.shadow_division, 1);
  EXPECT_EQ(transient.shadow_division, 1);
  const double cap = 1e6;
  const double extra_steady = noise_targeted_cost(steady, 1e9, cap).sun_rays - 2.0 * steady.sun_rays;
  const double extra_transient = noise_targeted_cost(transient, 1e9, cap).sun_rays - 2.0 * transient.sun_rays;
  EXPECT_DOUBLE_EQ(extra_transient, cap * transient.shadow_passes);
  EXPECT_DOUBLE_EQ(extra_steady, cap * steady.shadow_passes / steady.shadow_division);
  // The IR rays and Earth rays are traced once a run: the estimating run, the boosted run and
  // the extra samples, the cap binding when max_extra does not.
  const SimulationCost c = noise_targeted_cost(transient, 2.0, 1e300);
  EXPECT_DOUBLE_EQ(c.ir_rays, 4.0 * transient.ir_rays);
  EXPECT_DOUBLE_EQ(c.earth_rays, 4.0 * transient.earth_rays);
}

// The reduction driver on a small model that simulates in milliseconds: a subdivided cube
// (six nodes) with a two-sided panel beside it, in a fixed sun (steady state).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <nlohmann/json.hpp>

#include "common/scratch_dir.h"
#include "thermodec/common/errors.h"
#include "thermodec/decimation/decimate_nodes.h"
#include "thermodec/nodes/load_case.h"
#include "thermodec/nodes/load_model.h"
#include "thermodec/rays/surface_sides.h"
#include "thermodec/reduction/record_budget.h"
#include "thermodec/reduction/reduce_model.h"
#include "thermodec/reduction/statistical_verification.h"
#include "thermodec/report/reduction_report.h"
#include "thermodec/thermal/simulate_model.h"
#include "thermodec/thermal/temperature_noise.h"

using namespace thermodec;
namespace fs = std::filesystem;

namespace {

// Adds an n x n grid quad (corner o, edges u, v) as 2 n^2 triangles of node `node`.
void add_grid(Mesh& m, std::vector<std::array<double, 3>>& V, std::vector<std::array<int, 4>>& F,
              const Eigen::Vector3d& o, const Eigen::Vector3d& u, const Eigen::Vector3d& v, int n, int node) {
  const int base = static_cast<int>(V.size());
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const Eigen::Vector3d p = o + u * (double(i) / n) + v * (double(j) / n);
      V.push_back({p.x(), p.y(), p.z()});
    }
  auto id = [&](int i, int j) { return base + j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      F.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), node});
      F.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1), node});
    }
}

ThermalModel small_model() {
  Mesh m;
  std::vector<std::array<double, 3>> V;
  std::vector<std::array<int, 4>> F;
  const int n = 4;
  using V3 = Eigen::Vector3d;
  // cube [0,1]^3, outward normals (u x v points out)
  add_grid(m, V, F, V3(1, 0, 0), V3(0, 1, 0), V3(0, 0, 1), n, 0);  // +x
  add_grid(m, V, F, V3(0, 0, 0), V3(0, 0, 1), V3(0, 1, 0), n, 1);  // -x
  add_grid(m, V, F, V3(0, 1, 0), V3(0, 0, 1), V3(1, 0, 0), n, 2);  // +y
  add_grid(m, V, F, V3(0, 0, 0), V3(1, 0, 0), V3(0, 0, 1), n, 3);  // -y
  add_grid(m, V, F, V3(0, 0, 1), V3(1, 0, 0), V3(0, 1, 0), n, 4);  // +z
  add_grid(m, V, F, V3(0, 0, 0), V3(0, 1, 0), V3(1, 0, 0), n, 5);  // -z
  add_grid(m, V, F, V3(0, 1.3, 0), V3(0, 0, 1), V3(1, 0, 0), 6, 6);  // panel facing +y... and -y
  m.V.resize(V.size(), 3);
  for (size_t i = 0; i < V.size(); ++i) m.V.row(i) << V[i][0], V[i][1], V[i][2];
  m.F.resize(F.size(), 3);
  m.face_node.resize(F.size());
  m.face_material = Eigen::VectorXi::Zero(F.size());
  m.face_back_material = Eigen::VectorXi::Constant(F.size(), -1);
  for (size_t f = 0; f < F.size(); ++f) {
    m.F.row(f) << F[f][0], F[f][1], F[f][2];
    m.face_node[f] = F[f][3];
    if (F[f][3] == 6) m.face_back_material[f] = 0;
  }
  ThermalModel model;
  model.materials = {{"white_paint", 0.2, 0.85}};
  const char* names[] = {"px", "mx", "py", "my", "pz", "mz", "panel"};
  for (int k = 0; k < 7; ++k) {
    Node node;
    node.name = names[k];
    node.material = 0;
    node.capacitance_J_per_K = 1000.0;
    node.power_W = k < 6 ? 10.0 : 0.0;
    model.nodes.push_back(node);
    m.node_names.push_back(names[k]);
  }
  m.material_names = {"white_paint"};
  model.mesh = m;
  for (int k = 0; k < 6; ++k) model.conductances.push_back({k, (k + 1) % 6, 0.5});
  model.environment.type = EnvironmentType::fixed_sun;
  model.environment.sun_direction = Eigen::Vector3d(0.3, -1.0, 0.4).normalized();
  model.analysis.type = AnalysisType::steady;
  model.radiation.rays_per_face = 2000;
  model.radiation.seed = 7;
  return model;
}

ReduceSettings quick_settings(double tol) {
  ReduceSettings s;
  s.tolerance_K = tol;
  s.reference.simulation.loads.earth_rays_per_face = 16;
  s.reference.simulation.loads.sun_rays_per_face = 256;
  s.sensitivity.ratios = {0.3, 0.6, 0.8, 0.9};
  s.prediction_targets = {0.5, 1.0};
  return s;
}

}  // namespace

TEST(ReductionReference, incremental_trials_match_full_recompute) {
  const ThermalModel model = small_model();
  ReductionReferenceSettings rs;
  rs.simulation.loads.earth_rays_per_face = 16;
  rs.simulation.loads.sun_rays_per_face = 256;
  ReductionReference ref(model, rs);
  EXPECT_NO_THROW(ref.set_decimation_options(rs.decimation));  // before any trial: allowed
  const Eigen::VectorXd none = Eigen::VectorXd::Zero(7);
  EXPECT_EQ(ref.trial(none).max_abs_dT_K, 0.0);  // unchanged model: no difference at all
  // ... because nothing was decimated: the same mesh, so the trial is the reference itself
  const DecimationResult d = decimate_nodes(model.mesh, none, rs.decimation);
  EXPECT_TRUE(d.mesh.V == model.mesh.V && d.mesh.F == model.mesh.F && d.mesh.face_node == model.mesh.face_node);
  Eigen::VectorXd one = none;
  one[6] = 0.8;  // only the panel changes
  const TrialResult inc = ref.trial(one);
  const TrialResult full = ref.verify(one);
  EXPECT_LT(inc.node_faces_after[6], 72);
  EXPECT_NEAR(inc.max_abs_dT_K, full.max_abs_dT_K, 1e-6);
  // Memoised trials were decimated with the current options: changing them now is refused.
  EXPECT_THROW(ref.set_decimation_options(rs.decimation), InvalidInput);
  // Other ratios that decimate to the same mesh (here: the panel at the end of its reach) are
  // answered by the trial of that mesh, not simulated again.
  Eigen::VectorXd a = none, b = none;
  a[6] = 0.998;
  b[6] = 0.999;
  ASSERT_TRUE(decimate_nodes(model.mesh, a, rs.decimation).mesh.V == decimate_nodes(model.mesh, b, rs.decimation).mesh.V);
  const int before = ref.trials_evaluated();
  const TrialResult ta = ref.trial(a), tb = ref.trial(b);
  EXPECT_EQ(ref.trials_evaluated(), before + 1);
  EXPECT_EQ(ta.max_abs_dT_K, tb.max_abs_dT_K);
  EXPECT_EQ(ta.node_faces_after, tb.node_faces_after);
}

// Rebased on a candidate, trials near it re-trace from it yet give what the original gives:
// each is still compared with the original's result, and both ways equal a full recompute.
TEST(ReductionReference, rebased_trials_match_the_original_ones) {
  const ThermalModel model = small_model();
  ReductionReferenceSettings rs;
  rs.simulation.loads.earth_rays_per_face = 16;
  rs.simulation.loads.sun_rays_per_face = 256;
  ReductionReference ref(model, rs), rebased(model, rs);
  Eigen::VectorXd start = Eigen::VectorXd::Constant(7, 0.5);
  start[6] = 0.0;
  Eigen::VectorXd pushed = start, far = Eigen::VectorXd::Zero(7);
  pushed[0] = 0.8;  // one node further than the start: nearer the start than the original
  far[6] = 0.8;     // one node, none of the start's: nearer the original
  rebased.rebase(start, std::size_t(64) << 20);
  for (const Eigen::VectorXd& r : {start, pushed, far}) {
    const TrialResult a = ref.trial(r), b = rebased.trial(r);
    EXPECT_EQ(a.faces_after, b.faces_after);
    EXPECT_NEAR(a.max_abs_dT_K, b.max_abs_dT_K, 1e-6);
    EXPECT_GT(a.max_abs_dT_K, 0.0);
    ASSERT_EQ(a.dT_K.rows(), b.dT_K.rows());
    EXPECT_LT((a.dT_K - b.dT_K).cwiseAbs().maxCoeff(), 1e-6);
  }
  EXPECT_NEAR(rebased.trial(pushed).max_abs_dT_K, rebased.verify(pushed).max_abs_dT_K, 1e-6);
  // The candidate of an evaluated trial is rebuilt from memory: its result is the trial's.
  const int before = rebased.trials_evaluated();
  const Candidate c = rebased.candidate(pushed, false);
  EXPECT_EQ(rebased.trials_evaluated(), before);
  EXPECT_EQ(c.trial.max_abs_dT_K, rebased.trial(pushed).max_abs_dT_K);
  EXPECT_EQ(c.model.mesh.num_faces(), c.trial.faces_after);
}

TEST(ReductionReference, trials_do_not_depend_on_the_ray_record_budget) {
  // Without room for records, trials re-trace every ray near the change: slower, same numbers.
  const RecordBudget split = split_record_budget(default_record_budget_bytes());
  EXPECT_LE(split.records_bytes + split.earth_geometry_bytes, default_record_budget_bytes());
  EXPECT_LE(split.ir_max_bytes, split.records_bytes);
  const RecordBudget standard = split_record_budget(std::size_t(17) << 28);  // 4.25 GiB
  EXPECT_EQ(standard.earth_geometry_bytes, std::size_t(1) << 29);
  EXPECT_EQ(standard.load_bytes(0), standard.records_bytes);  // IR records left out: all to sun/Earth
  EXPECT_GE(standard.load_bytes(standard.ir_max_bytes), standard.records_bytes / 4);
  const ThermalModel model = small_model();
  ReductionReferenceSettings rs;
  rs.simulation.loads.earth_rays_per_face = 16;
  rs.simulation.loads.sun_rays_per_face = 256;
  ReductionReferenceSettings starved = rs;
  starved.record_budget_bytes = 17;  // a few bytes: no record fits
  ReductionReference with(model, rs), without(model, starved);
  Eigen::VectorXd r = Eigen::VectorXd::Zero(7);
  r[6] = 0.8;
  r[0] = 0.5;
  const TrialResult a = with.trial(r), b = without.trial(r);
  EXPECT_EQ(a.max_abs_dT_K, b.max_abs_dT_K);
  EXPECT_EQ(a.node_max_abs_dT_K, b.node_max_abs_dT_K);
}

TEST(ReductionReference, trial_noise_floor_redraws_one_node_at_a_time_as_a_full_run_would) {
  ThermalModel model = small_model();
  ReductionReferenceSettings rs;
  rs.simulation.loads.earth_rays_per_face = 16;
  rs.simulation.loads.sun_rays_per_face = 256;
  const ReductionReference ref(model, rs);
  const TrialNoiseFloor tn = ref.trial_noise_floor(7);
  ASSERT_EQ(tn.node_max_abs_dT_K.size(), 7);
  EXPECT_GT(tn.worst.max_abs_K, 0.0);  // redrawn samples: Monte Carlo noise, but small
  EXPECT_LT(tn.worst.max_abs_K, 0.5);
  EXPECT_EQ(tn.worst.max_abs_K, tn.node_max_abs_dT_K.maxCoeff());
  // The incremental evaluation equals a full simulation of the salted model.
  const int k = tn.worst_resampled_node;
  ThermalModel salted = model;
  salted.nodes[k].sampling_salt = 7;
  ModelSimulationSettings plain = rs.simulation;
  plain.planar_strata = false;  // (as a reduction's reference traces)
  const double full = compare_results(ref.result(), simulate_model(salted, plain)).max_abs_K;
  EXPECT_NEAR(tn.node_max_abs_dT_K[k], full, 1e-6);
}

TEST(SurfaceSides, sampling_salt_changes_the_identity_of_its_node_sides_only) {
  ThermalModel model = small_model();
  const SurfaceSides a = surface_sides(model);
  model.nodes[6].sampling_salt = 3;
  const SurfaceSides b = surface_sides(model);
  ASSERT_EQ(a.size(), b.size());
  for (int s = 0; s < a.size(); ++s) EXPECT_EQ(a.key[s] != b.key[s], a.node[s] == 6) << "side " << s;
}

TEST(SurfaceSides, sampling_boost_multiplies_its_node_sides_samples_only) {
  ThermalModel model = small_model();
  const Eigen::VectorXi a = rays_per_side_of_node(surface_sides(model), 100, 5000);
  model.nodes[6].sampling_boost = {4.0, 2.0};
  const SurfaceSides sides = surface_sides(model);
  const Eigen::VectorXi b = rays_per_side_of_node(sides, 100, 5000, sides.ir_boost);
  const Eigen::VectorXi c = rays_per_side_of_node(sides, 100, 5000, sides.load_boost);
  for (int s = 0; s < sides.size(); ++s) {
    if (sides.node[s] == 6) {
      EXPECT_GE(b[s], 4 * a[s] - 4) << "side " << s;
      EXPECT_LE(b[s], 4 * a[s] + 1) << "side " << s;
      EXPECT_GE(c[s], 2 * a[s] - 2) << "side " << s;
      EXPECT_LE(c[s], 2 * a[s] + 1) << "side " << s;
    } else {
      EXPECT_EQ(b[s], a[s]) << "side " << s;
      EXPECT_EQ(c[s], a[s]) << "side " << s;
    }
  }
  // a multiplier below 1 divides them (thinning), down to 1/64
  model.nodes[6].sampling_boost = {0.25, 0.5};
  const SurfaceSides thin = surface_sides(model);
  const Eigen::VectorXi d = rays_per_side_of_node(thin, 100, 5000, thin.ir_boost);
  for (int s = 0; s < thin.size(); ++s)
    if (thin.node[s] == 6) EXPECT_EQ(d[s], (a[s] + 3) / 4) << "side " << s;
  model.nodes[6].sampling_boost.loads = 1.0 / 128.0;
  EXPECT_THROW(surface_sides(model), InvalidInput);
}

TEST(SamplingBoosts, noisy_nodes_are_boosted_within_the_extra_ray_cap_and_kept_by_model_files) {
  ThermalModel model = small_model();
  model.radiation.rays_per_face = 50;
  ModelSimulationSettings ss;
  ss.loads.earth_rays_per_face = 16;
  const SamplingBoosts b = decide_sampling_boosts(model, ss, 1e-4, 2.0);
  ASSERT_EQ(b.boost.size(), model.nodes.size());
  EXPECT_GE(b.target_K, 1e-4);
  EXPECT_LE(b.extra_ir_rays, 2.0);
  EXPECT_LE(b.extra_load_samples, 2.0);
  EXPECT_TRUE(b.any());
  // a tighter cap (simulate --noise-budget) gives fewer extra samples for a looser target
  const SamplingBoosts tight = decide_sampling_boosts(model, ss, 1e-4, 0.5);
  EXPECT_LE(tight.extra_ir_rays, 0.5);
  EXPECT_LE(tight.extra_load_samples, 0.5);
  EXPECT_GE(tight.target_K, b.target_K);
  // an absolute cap (simulate --noise-max-samples) binds where it is below the multiple
  const double cap = 0.25 * std::min(b.ir_rays, b.load_samples);
  const SamplingBoosts counted = decide_sampling_boosts(model, ss, 1e-4, 2.0, cap);
  EXPECT_GT(b.ir_rays, 0.0);
  EXPECT_LE(counted.extra_ir_rays * counted.ir_rays, cap);
  EXPECT_LE(counted.extra_load_samples * counted.load_samples, cap);
  EXPECT_GE(counted.target_K, tight.target_K);
  EXPECT_THROW(decide_sampling_boosts(model, ss, 1e-4, -1.0), InvalidInput);
  for (std::size_t k = 0; k < b.boost.size(); ++k) model.nodes[k].sampling_boost = b.boost[k];
  EXPECT_TRUE(has_sampling_boosts(model));
  const fs::path dir = thermodec::test::scratch_dir("thermodec_test", "boost");
  save_model(model, dir / "m.json", dir / "m.obj");
  const ThermalModel back = load_model(dir / "m.json");
  for (std::size_t k = 0; k < b.boost.size(); ++k) EXPECT_TRUE(back.nodes[k].sampling_boost == b.boost[k]) << k;
  // a boost below 1/64 in a model file is refused with the key named
  std::ifstream in(dir / "m.json");
  nlohmann::json j = nlohmann::json::parse(in);
  j["nodes"]["px"]["sampling_boost"] = {{"ir", 1.0 / 128.0}};
  std::ofstream(dir / "bad.json") << j.dump();
  try {
    load_model(dir / "bad.json");
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("sampling_boost"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

TEST(SamplingBoosts, a_model_far_under_the_target_is_thinned_by_one_common_factor_per_kind) {
  ThermalModel model = small_model();
  ModelSimulationSettings ss;
  ss.loads.earth_rays_per_face = 16;
  const double inf = std::numeric_limits<double>::infinity();
  // simulate's call (min_boost 1) never thins; reduce's (1/64) does, one factor per kind
  const SamplingBoosts kept = decide_sampling_boosts(model, ss, 1.0, 2.0, inf);
  EXPECT_FALSE(kept.any());
  const SamplingBoosts thin = decide_sampling_boosts(model, ss, 1.0, 2.0, inf, Node::SamplingBoost::kMin);
  ASSERT_TRUE(thin.any());
  const double ir = thin.boost.front().ir, loads = thin.boost.front().loads;
  EXPECT_LT(std::min(ir, loads), 1.0);
  for (const auto& b : thin.boost) EXPECT_TRUE((b == Node::SamplingBoost{ir, loads}));
  EXPECT_EQ(ir, noise_targeted_thinning(thin.ir_standard_error_K, 1.0));
  EXPECT_EQ(loads, noise_targeted_thinning(thin.load_standard_error_K, 1.0));
  EXPECT_NEAR(thin.extra_ir_rays, ir - 1.0, 1e-12);  // every node thinned alike
  EXPECT_NE(thin.describe(model.nodes).find("every node"), std::string::npos) << thin.describe(model.nodes);
  // a node above the target is boosted, and then its kind is not thinned
  const SamplingBoosts tight = decide_sampling_boosts(model, ss, 1e-4, 2.0, inf, Node::SamplingBoost::kMin);
  for (const auto& b : tight.boost) EXPECT_GE(std::min(b.ir, b.loads), 1.0);
}

TEST(ReduceSettings, large_model_files_sweep_on_halving_face_counts_and_small_ones_keep_the_grid) {
  ThermalModel model = small_model();
  ReduceSettings s;
  const std::vector<double> grid = s.sensitivity.ratios;
  apply_large_model_sweep(model, s);  // 312 faces: the fixed grid
  EXPECT_EQ(s.sensitivity.ratios, grid);
  model.mesh.F = Eigen::MatrixXi::Zero(kBareMeshCoarseSweepFaces + 1, 3);  // only the count is read
  apply_large_model_sweep(model, s);
  EXPECT_EQ(s.sensitivity.ratios,
            (std::vector<double>{0.5, 0.75, 0.875, 0.9375, 0.96875, 0.984375, 0.9921875}));
  ReduceSettings bare;
  model.mesh_cleanup.emplace();  // a bare mesh keeps its own budget
  apply_large_model_sweep(model, bare);
  EXPECT_EQ(bare.sensitivity.ratios, grid);
}

TEST(ReduceModel, informed_result_is_verified_within_tolerance_by_an_independent_simulation) {
  const ThermalModel model = small_model();
  const double tol = 0.5;
  const ReductionRun run = reduce_model(model, quick_settings(tol));
  EXPECT_LT(run.faces_after, run.faces_before);
  EXPECT_LE(run.max_temperature_difference_K, tol);
  // independent check: plain simulations of both models, nothing shared with the driver
  ModelSimulationSettings ss;
  ss.loads.earth_rays_per_face = 16;
  ss.loads.sun_rays_per_face = 256;
  const auto a = simulate_model(model, ss);
  const auto b = simulate_model(run.reduced.model, ss);
  EXPECT_LE(compare_results(a, b).max_abs_K, tol);
  ASSERT_EQ(run.nodes.size(), 7u);
  for (const auto& n : run.nodes) EXPECT_GE(n.faces_after, 1);
  EXPECT_EQ(run.curves.size(), 7u);
  // The predicted-vs-real target at the search tolerance is the search's first candidate.
  bool memoised_point = false;
  for (const PredictionPoint& p : run.prediction)
    if (p.target_K == run.search_tolerance_K) {
      memoised_point = true;
      EXPECT_EQ(p.real_K, run.outcome.history.front().result.max_abs_dT_K);
      EXPECT_EQ(p.faces_after, run.outcome.history.front().result.faces_after);
    }
  EXPECT_TRUE(memoised_point);
  // The decimator's area bound comes from the tolerance: area drift dT = T dA / (4 A) may
  // cost at most area_error_fraction (default 0.1) of it at the hottest reference temperature.
  const double t_max = run.reference.temperature_K.maxCoeff();
  EXPECT_DOUBLE_EQ(run.max_relative_area_change, std::min(0.005, 4.0 * ReduceSettings{}.area_error_fraction * tol / t_max));
  EXPECT_LT(run.max_relative_area_change, 0.005);
  // Per node, the same share of the tolerance against the node's own sensitivity to its area
  // (reduction/area_bounds.h), at most the decimator's 0.5 %.
  ASSERT_EQ(run.node_max_relative_area_change.size(), run.nodes.size());
  for (std::size_t i = 0; i < run.nodes.size(); ++i) {
    const double bound = run.node_max_relative_area_change[i];
    EXPECT_GT(bound, 0.0);
    EXPECT_LE(bound, 0.005);
    const auto& n = run.nodes[i];
    EXPECT_LE(std::abs(n.area_after_m2 / n.area_before_m2 - 1.0), bound + 1e-12) << n.name;
  }
}

TEST(ReduceModel, extra_load_cases_are_all_verified_and_the_worst_one_is_reported) {
  const ThermalModel model = small_model();
  const double tol = 0.5;
  ReduceSettings s = quick_settings(tol);
  LoadCase other = own_case(model, "other_sun");
  other.environment.sun_direction = Eigen::Vector3d(-0.5, 0.8, -0.2).normalized();  // lights the panel's other face
  s.extra_cases.push_back(other);
  const ReductionRun run = reduce_model(model, s);
  ASSERT_EQ(run.cases.size(), 2u);
  EXPECT_EQ(run.cases[0].name, "model");
  EXPECT_EQ(run.cases[1].name, "other_sun");
  EXPECT_LT(run.faces_after, run.faces_before);
  double worst = 0.0;
  for (const auto& c : run.cases) {
    EXPECT_LE(c.max_temperature_difference_K, tol) << c.name;
    EXPECT_GT(c.noise_floor_K, 0.0) << c.name;
    worst = std::max(worst, c.max_temperature_difference_K);
  }
  EXPECT_EQ(run.max_temperature_difference_K, worst);
  // The record budget is the run's: the two references share it.
  for (const auto& c : run.cases) {
    EXPECT_EQ(c.ray_record_budget_bytes, default_record_budget_bytes() / 2) << c.name;
    EXPECT_GT(c.ray_record_bytes, 0u) << c.name;
    EXPECT_LE(c.ray_record_bytes, c.ray_record_budget_bytes) << c.name;
    EXPECT_GT(c.view_factor_bytes, 0u) << c.name;  // (kept outside the budget)
  }
  // independent check in both environments: plain simulations, nothing shared with the driver
  ModelSimulationSettings ss;
  ss.loads.earth_rays_per_face = 16;
  ss.loads.sun_rays_per_face = 256;
  for (const LoadCase& c : {own_case(model), other}) {
    const auto a = simulate_model(with_case(model, c), ss);
    const auto b = simulate_model(with_case(run.reduced.model, c), ss);
    EXPECT_LE(compare_results(a, b).max_abs_K, tol) << c.name;
  }
  // per node: the worst over the cases
  for (const auto& n : run.nodes) EXPECT_LE(n.max_abs_dT_K, run.max_temperature_difference_K + 1e-12);
}

TEST(LoadCase, case_files_override_the_models_environment_and_name_their_bad_keys) {
  const fs::path dir = thermodec::test::scratch_dir("thermodec_test", "load_case");
  ThermalModel model = small_model();
  model.environment.type = EnvironmentType::orbit;
  model.environment.day_of_year = 172;
  model.environment.altitude_km = 700.0;
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return dir / name;
  };
  const LoadCase c = load_case(write("cold.json", R"({"environment": {"type": "orbit", "day_of_year": 355}})"), model);
  EXPECT_EQ(c.name, "cold");  // the file's stem
  EXPECT_EQ(c.environment.day_of_year, 355);
  EXPECT_EQ(c.environment.altitude_km, 700.0);  // kept from the model
  EXPECT_EQ(with_case(model, c).environment.day_of_year, 355);
  EXPECT_EQ(with_case(model, c).mesh.num_faces(), model.mesh.num_faces());
  const LoadCase named = load_case(write("n.json", R"({"name": "hot", "analysis": {"type": "steady"}})"), model);
  EXPECT_EQ(named.name, "hot");
  for (const auto& [text, needle] : std::vector<std::pair<std::string, std::string>>{
           {R"({"environment": {"type": "orbit", "day_of_yaer": 3}})", "day_of_yaer"},
           {R"({"environment": {"type": "orbit", "day_of_year": 400}})", "day_of_year"},
           {R"({"enviroment": {}})", "enviroment"},
           {R"({"environment": {"type": "fixed_sun"}, "analysis": {"type": "transient_orbit"}})", "transient_orbit"},
           {R"([1, 2])", "object"},
           {R"({"name": ""})", "name"},
           {R"({"environment": )", "invalid JSON"}}) {
    try {
      load_case(write("bad.json", text), model);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(load_case(dir / "missing.json", model), IOError);
  fs::remove_all(dir);
}

TEST(ReduceModel, uniform_result_is_verified_within_tolerance) {
  const ThermalModel model = small_model();
  ReduceSettings s = quick_settings(0.5);
  s.strategy = ReductionStrategy::uniform;
  s.uniform.step = 0.2;
  const ReductionRun run = reduce_model(model, s);
  EXPECT_LE(run.max_temperature_difference_K, 0.5);
  EXPECT_LE(run.faces_after, run.faces_before);
  // The verification took its first original from the noise floor's run (its seed s_0): the same
  // statistics, to the bit, as a verification that simulates every original itself.
  ThermalModel original = model;
  for (std::size_t k = 0; k < original.nodes.size(); ++k) original.nodes[k].sampling_boost = run.sampling_boost[k];
  ModelSimulationSettings ss = s.reference.simulation;
  ss.loads.earth_view_by_rays = true;  // (as reduce_model simulates)
  ss.planar_strata = false;
  const VerificationStatistics v = verify_statistically({{&original, &run.reduced.model}}, ss,
                                                        s.verification_replicates, model.radiation.seed);
  EXPECT_EQ(v.seeds, run.verification.seeds);
  // ... and that run is the noise floor's: the original at s_0 against the original at the
  // model's seed (the reference) gives the run's noise floor.
  ThermalModel at_s0 = original, at_seed = original;
  at_s0.radiation.seed = v.seeds.front();
  const double floor = compare_results(simulate_model(at_seed, ss), simulate_model(at_s0, ss)).max_abs_K;
  EXPECT_EQ(floor, run.noise_floor_K);
  EXPECT_EQ(v.upper_bound_K, run.verification.upper_bound_K);
  EXPECT_EQ(v.max_abs_dT_K, run.verification.max_abs_dT_K);
}

TEST(ReduceModel, same_input_gives_same_reduction) {
  const ThermalModel model = small_model();
  const ReductionRun a = reduce_model(model, quick_settings(0.5));
  const ReductionRun b = reduce_model(model, quick_settings(0.5));
  EXPECT_EQ(a.faces_after, b.faces_after);
  EXPECT_EQ(a.outcome.ratio_per_node, b.outcome.ratio_per_node);
  EXPECT_EQ(a.max_temperature_difference_K, b.max_temperature_difference_K);
}

TEST(ReduceModel, impossible_tolerances_are_refused) {
  const ThermalModel model = small_model();
  for (double tol : {0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity()})
    EXPECT_THROW(reduce_model(model, quick_settings(tol)), InvalidInput) << tol;
  for (double f : {-0.1, 1.5, std::nan("")}) {
    ReduceSettings s = quick_settings(0.5);
    s.area_error_fraction = f;
    EXPECT_THROW(reduce_model(model, s), InvalidInput) << f;
  }
  // below twice the measured Monte Carlo noise floor (noise is > 0 with few rays)
  ThermalModel noisy = model;
  noisy.radiation.rays_per_face = 50;
  try {
    reduce_model(noisy, quick_settings(1e-7));
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("noise floor"), std::string::npos) << e.what();
  }
}

TEST(ReduceCli, writes_loadable_model_and_report_with_required_keys) {
  const fs::path dir = thermodec::test::scratch_dir("thermodec_test", "reduce_cli");
  ThermalModel model = small_model();
  save_model(model, dir / "in.json", dir / "in.obj");
  const fs::path out = dir / "out";
  const std::string cmd = std::string(THERMODEC_CLI) + " reduce " + (dir / "in.json").string() +
                          " --tolerance 0.5 --out " + out.string() + " --no-plots -q > " +
                          (dir / "stdout.txt").string() + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  std::ifstream in(out / "report.json");
  const auto j = nlohmann::json::parse(in);
  for (const char* key : {"strategy", "tolerance_K", "faces_before", "faces_after", "max_temperature_difference_K",
                          "noise_floor_K", "nodes"})
    EXPECT_TRUE(j.contains(key)) << key;
  for (const char* key : {"faces_before", "faces_after", "ratio", "max_abs_dT_K", "target_faces", "faces_removed",
                          "stopped_by", "blocked_edges"})
    EXPECT_TRUE(j["nodes"]["panel"].contains(key)) << key;
  // Reach: what the ratio removed, and why a node ended above its target (or "none").
  for (const auto& [name, n] : j["nodes"].items()) {
    EXPECT_EQ(n["faces_removed"].get<int>(), n["faces_before"].get<int>() - n["faces_after"].get<int>()) << name;
    const bool reached = n["faces_after"].get<int>() <= n["target_faces"].get<int>();
    EXPECT_EQ(n["blocked_edges"].empty(), reached) << name;
    if (reached) EXPECT_EQ(n["stopped_by"], "none") << name;
  }
  EXPECT_LE(j["max_temperature_difference_K"].get<double>(), 0.5);
  const ThermalModel reduced = load_model(out / "model.json");
  EXPECT_EQ(reduced.mesh.num_faces(), j["faces_after"].get<int>());
  EXPECT_EQ(reduced.nodes.size(), model.nodes.size());

  // bad tolerance: exit code 1 and a one-line reason
  const std::string bad = std::string(THERMODEC_CLI) + " reduce " + (dir / "in.json").string() +
                          " --tolerance -1 --out " + (dir / "bad").string() + " -q 2> " + (dir / "err.txt").string();
  EXPECT_EQ(WEXITSTATUS(std::system(bad.c_str())), 1);

  // a load case named like the model's own: refused before any simulation, with the reason
  std::ofstream(dir / "model_case.json") << R"({"name": "model", "environment": {"type": "fixed_sun"}})";
  const std::string dup = std::string(THERMODEC_CLI) + " reduce " + (dir / "in.json").string() + " --case " +
                          (dir / "model_case.json").string() + " --out " + (dir / "dup").string() + " -q 2> " +
                          (dir / "dup_err.txt").string();
  EXPECT_EQ(WEXITSTATUS(std::system(dup.c_str())), 1);
  std::stringstream err;
  err << std::ifstream(dir / "dup_err.txt").rdbuf();
  EXPECT_NE(err.str().find("used twice"), std::string::npos) << err.str();
  EXPECT_FALSE(fs::exists(dir / "dup"));
}

TEST(ReduceModel, every_attempt_rejected_backs_the_least_rejected_candidate_off_towards_the_unreduced_model) {
  // A verifier that accepts a candidate keeping at least `floor` faces: the search's candidates
  // (reduced further) are all rejected, a half-way back-off is accepted.
  const ThermalModel model = small_model();
  const int before = model.mesh.num_faces();
  ReduceSettings s = quick_settings(0.5);
  s.verification_attempts = 1;
  const ReductionRun plain = reduce_model(model, s);
  ASSERT_LT(plain.faces_after, before);
  const int floor = (before + plain.faces_after) / 2;
  std::vector<int> asked;
  s.verify_candidate = [&](const std::vector<const ThermalModel*>& c) {
    asked.push_back(c.front()->mesh.num_faces());
    VerificationStatistics v;
    v.upper_bound_K = asked.back() >= floor ? 0.1 : 1.0;
    return v;
  };
  const ReductionRun none = reduce_model(model, s);  // back_off_verifications = 0: unreduced
  EXPECT_EQ(none.faces_after, before);
  ASSERT_EQ(asked.size(), 2u);  // the rejected candidate, then the unreduced model
  asked.clear();
  s.back_off_verifications = 2;
  const ReductionRun backed = reduce_model(model, s);
  ASSERT_EQ(asked.size(), 3u);  // rejected, then x 1/2 and x 3/4 or x 1/4
  EXPECT_LT(asked[0], floor);
  EXPECT_GT(asked[1], asked[0]);
  EXPECT_LT(backed.faces_after, before);
  EXPECT_GE(backed.faces_after, floor);
  EXPECT_TRUE(backed.verification.accepts(0.5));
  EXPECT_EQ(backed.outcome.history.back().action.rfind("back off x", 0), 0u) << backed.outcome.history.back().action;
  EXPECT_GT(backed.outcome.ratio_per_node.maxCoeff(), 0.0);
}

TEST(ReductionReference, decimation_that_drops_only_unused_vertices_is_the_reference) {
  // A vertex no face uses (a cleaned mesh can keep some: Juno's dropped degenerate faces). A
  // decimation that collapses nothing leaves it out, so the vertex table differs while every
  // face keeps its corners: the same surface, whose trial is the reference itself, not a new
  // simulation (on Juno such a trial sampled every load again).
  ThermalModel model = small_model();
  const Eigen::Index nv = model.mesh.V.rows();
  model.mesh.V.conservativeResize(nv + 1, 3);
  model.mesh.V.row(nv) << 5.0, 5.0, 5.0;
  ReductionReferenceSettings rs;
  rs.simulation.loads.earth_rays_per_face = 16;
  rs.simulation.loads.sun_rays_per_face = 256;
  ReductionReference ref(model, rs);
  const Eigen::VectorXd none = Eigen::VectorXd::Zero(7);
  const DecimationResult d = decimate_nodes(model.mesh, none, rs.decimation);
  ASSERT_EQ(d.mesh.V.rows(), nv);  // the unused vertex is gone ...
  ASSERT_EQ(d.mesh.F, model.mesh.F);  // ... and the faces are the same
  const TrialResult t = ref.trial(none);
  EXPECT_EQ(t.max_abs_dT_K, 0.0);
  EXPECT_EQ(t.redone_fraction, 0.0);
  EXPECT_EQ(t.timing.couplings_s, 0.0);  // nothing traced or sampled again
  EXPECT_EQ(t.timing.loads_s, 0.0);
  EXPECT_EQ(t.timing.solve_s, 0.0);
  EXPECT_EQ(ref.verify(none).max_abs_dT_K, 0.0);  // what a full simulation of it gives
  // A decimated node is a change, traced as one.
  Eigen::VectorXd one = none;
  one[6] = 0.8;
  const TrialResult moved = ref.trial(one);
  EXPECT_GT(moved.redone_fraction, 0.0);
  EXPECT_GT(moved.timing.loads_s + moved.timing.couplings_s, 0.0);
}

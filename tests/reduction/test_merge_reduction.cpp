// Merged networks (reduction/merged_network.h) and the merge search (reduction/merge_reduction.h)
// on the sample satellite with few rays and a steady analysis (a network solve in milliseconds).
#include <gtest/gtest.h>

#include <filesystem>

#include "thermodec/common/errors.h"
#include "thermodec/nodes/load_model.h"
#include "thermodec/reduction/merge_reduction.h"
#include "thermodec/thermal/simulate_model.h"

namespace fs = std::filesystem;
using namespace thermodec;

namespace {

const fs::path kSample = fs::path(THERMODEC_SOURCE_DIR) / "sample_models" / "satellite" / "model.json";

ThermalModel quick_sample() {
  ThermalModel m = load_model(kSample);
  m.radiation.rays_per_face = 200;
  m.radiation.min_rays_per_node = 0;
  m.analysis.type = AnalysisType::steady;
  return m;
}

NodeMergeMap merging(const ThermalModel& m, const std::vector<std::string>& group) {
  std::vector<int> label(m.nodes.size());
  int first = -1;
  for (std::size_t i = 0; i < label.size(); ++i) {
    label[i] = static_cast<int>(i);
    if (std::find(group.begin(), group.end(), m.nodes[i].name) != group.end()) {
      if (first < 0) first = static_cast<int>(i);
      label[i] = first;
    }
  }
  return node_merge_map(label, static_cast<int>(m.nodes.size()));
}

}  // namespace

TEST(MergedNetwork, couplings_and_loads_are_member_sums_without_the_inner_exchange) {
  if (!fs::exists(kSample)) GTEST_SKIP() << kSample << " not present";
  const ThermalModel m = quick_sample();
  NodeCouplings c;
  const SimulationResult r = simulate_model(m, {}, &c);
  const NodeMergeMap map = merging(m, {"body_px", "body_py", "body_pz"});
  const NodeCouplings mc = merge_couplings(c, map);
  const int n = static_cast<int>(m.nodes.size()), k = map.num_merged();
  ASSERT_EQ(k, n - 2);
  for (int a = 0; a < k; ++a) {
    double area = 0.0, space = 0.0;
    for (int i : map.members[a]) area += c.area_m2[i], space += c.to_space_couplings_m2[i];
    EXPECT_NEAR(mc.area_m2[a], area, 1e-12 * area);
    EXPECT_NEAR(mc.to_space_couplings_m2[a], space, 1e-12 * std::max(space, 1e-30));
    for (int b = 0; b < k; ++b) {
      double gr = 0.0;
      for (int i : map.members[a])
        for (int j : map.members[b]) gr += c.radiative_couplings_m2(i, j);
      EXPECT_NEAR(mc.radiative_couplings_m2(a, b), gr, 1e-12 * std::max(gr, 1e-30));
    }
    // Rows close as the members' do: a merged row is their area-weighted mean.
    double closure = 0.0;
    for (int i : map.members[a]) closure += c.area_m2[i] * (c.view_factors.row(i).sum() + c.to_space[i]);
    EXPECT_NEAR(mc.view_factors.row(a).sum() + mc.to_space[a], closure / area, 1e-9);
  }
  const Loads ml = merge_loads(r.loads, map);
  for (int a = 0; a < k; ++a) {
    Eigen::RowVectorXd sum = Eigen::RowVectorXd::Zero(r.loads.solar_W.cols());
    for (int i : map.members[a]) sum += r.loads.total_W().row(i);
    EXPECT_LE((ml.total_W().row(a) - sum).cwiseAbs().maxCoeff(), 1e-9 * (1.0 + sum.cwiseAbs().maxCoeff()));
  }
}

TEST(MergedNetwork, identity_merge_reproduces_the_reference_exactly) {
  if (!fs::exists(kSample)) GTEST_SKIP() << kSample << " not present";
  const ThermalModel m = quick_sample();
  NodeCouplings c;
  const SimulationResult r = simulate_model(m, {}, &c);
  std::vector<int> label(m.nodes.size());
  for (std::size_t i = 0; i < label.size(); ++i) label[i] = static_cast<int>(i);
  const NodeMergeMap id = node_merge_map(label, static_cast<int>(label.size()));
  const ThermalModel same = merge_nodes(m, id);
  const SimulationResult s = simulate(same, merge_couplings(c, id), merge_loads(r.loads, id), SimulationSettings{});
  EXPECT_EQ(compare_results(r, result_through_node_map(s, same.node_map)).max_abs_K, 0.0);
}

TEST(MergedNetwork, merged_result_is_read_per_original_node) {
  SimulationResult merged;
  merged.nodes = {"a+1", "c"};
  merged.times_s = Eigen::VectorXd::Zero(2);
  merged.temperature_K.resize(2, 2);
  merged.temperature_K << 300, 301, 250, 251;
  const SimulationResult r = result_through_node_map(merged, {{"a", "a+1"}, {"b", "a+1"}, {"c", "c"}});
  ASSERT_EQ(r.nodes, (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_EQ(r.temperature_K(1, 1), 301.0);
  EXPECT_EQ(r.temperature_K(2, 0), 250.0);
  EXPECT_THROW(result_through_node_map(merged, {{"a", "x"}}), InvalidInput);
}

TEST(MergeSearch, kept_and_fixed_nodes_are_never_merged_and_merges_stay_within_the_budget) {
  if (!fs::exists(kSample)) GTEST_SKIP() << kSample << " not present";
  ThermalModel m = quick_sample();
  m.nodes[0].fixed_temperature_K = 290.0;  // a boundary node
  NodeMergeSettings s;
  s.keep = {"dish", "instrument"};
  // A loose budget: the sample's nodes differ by tens of K, so only then do most nodes merge.
  const MergeSearch ms = search_node_merges(m, {}, {}, s, 30.0);
  EXPECT_LT(ms.map.num_merged(), static_cast<int>(m.nodes.size()));
  // Small nodes may take max(small_node_share, tolerance_share) of the tolerance (30 K / share).
  EXPECT_NEAR(ms.summary.small_budget_K, std::max(s.small_node_share, s.tolerance_share) * 30.0 / s.tolerance_share, 1e-9);
  EXPECT_LE(ms.summary.dT_K, ms.summary.small_budget_K);
  EXPECT_EQ(ms.summary.nodes_after, ms.map.num_merged());
  // The merges kept were re-traced within the whole tolerance (budget / share).
  EXPECT_GE(ms.summary.traced_simulations, 1);
  EXPECT_LE(ms.summary.traced_dT_K, 30.0 / s.tolerance_share);
  EXPECT_EQ(static_cast<int>(ms.summary.steps.size()), ms.summary.nodes_before - ms.summary.nodes_after);
  for (const std::string& kept : {std::string("dish"), std::string("instrument"), m.nodes[0].name}) {
    int i = 0;
    while (m.nodes[i].name != kept) ++i;
    EXPECT_EQ(ms.map.members[ms.map.merged_of_node[i]].size(), 1u) << kept;
    EXPECT_NE(std::find(ms.summary.kept.begin(), ms.summary.kept.end(), kept), ms.summary.kept.end());
  }
  // Without --keep-node the same search merges them (so the test above means something).
  const MergeSearch free_search = search_node_merges(m, {}, {}, NodeMergeSettings{}, 30.0);
  int merged_kept = 0;
  for (const std::string& kept : {std::string("dish"), std::string("instrument")}) {
    int i = 0;
    while (m.nodes[i].name != kept) ++i;
    merged_kept += free_search.map.members[free_search.map.merged_of_node[i]].size() > 1;
  }
  EXPECT_GT(merged_kept, 0);
  NodeMergeSettings bad;
  bad.keep = {"no_such_node"};
  EXPECT_THROW(search_node_merges(m, {}, {}, bad, 1.0), InvalidInput);
}

TEST(MergeSearch, small_nodes_are_the_fewest_faced_within_their_share_of_the_faces) {
  if (!fs::exists(kSample)) GTEST_SKIP() << kSample << " not present";
  const ThermalModel m = quick_sample();
  const int n = static_cast<int>(m.nodes.size());
  std::vector<int> faces(n, 0);
  for (int f = 0; f < m.mesh.num_faces(); ++f) ++faces[m.mesh.face_node[f]];
  for (double share : {0.0, 0.1, 0.3, 0.99}) {
    const std::vector<char> small = small_nodes(m, share);
    int held = 0, most_small = 0, least_other = m.mesh.num_faces() + 1;
    for (int i = 0; i < n; ++i) {
      if (small[i]) held += faces[i], most_small = std::max(most_small, faces[i]);
      else least_other = std::min(least_other, faces[i]);
    }
    EXPECT_LE(held, share * m.mesh.num_faces()) << share;
    EXPECT_LE(most_small, least_other) << share;  // the fewest-faced ones
    if (least_other <= m.mesh.num_faces()) EXPECT_GT(held + least_other, share * m.mesh.num_faces()) << share;
  }
}

TEST(MergeSearch, best_first_and_cheapest_pairs_first_both_keep_every_node_within_its_budget) {
  if (!fs::exists(kSample)) GTEST_SKIP() << kSample << " not present";
  const ThermalModel m = quick_sample();
  for (bool best : {true, false}) {
    NodeMergeSettings s;
    s.best_first = best;
    s.small_node_share = 0.85;  // the joint allocation on
    s.confirm_by_tracing = false;
    const MergeSearch ms = search_node_merges(m, {}, {}, s, 12.0);
    EXPECT_LT(ms.map.num_merged(), static_cast<int>(m.nodes.size())) << best;
    EXPECT_LE(ms.summary.dT_K, ms.summary.small_budget_K) << best;
    for (const NodeMergeStep& st : ms.summary.steps) EXPECT_LE(st.dT_K, ms.summary.small_budget_K) << best;
  }
}

// Superposition anchored on a measured combined candidate, and the combined push that plans on
// it: exact at its anchor, plain superposition from the unreduced model, and a push over nodes
// that interact (their combined effect far above the sum of their single-node fields) that
// learns the interaction from its own measurements and still ends within the tolerance.
#include <gtest/gtest.h>

#include <cmath>

#include "thermodec/reduction/anchored_superposition.h"
#include "thermodec/reduction/combined_push.h"
#include "thermodec/reduction/sensitivity.h"
#include "thermodec/reduction/strategies.h"
#include "thermodec/reduction/superposition.h"

using namespace thermodec;

namespace {

// A network of n nodes, one cell per node and one output time: node k's own cell moves by
// s_k r_k^2 [K], and every pair (i, j) sharing an interface adds c r_i r_j to cell i, an
// interaction no single-node trial sees (each is zero when one ratio is zero).
struct Interacting {
  Eigen::VectorXd s_K;
  Eigen::MatrixXd pair_K;  // c for each (i, j), i != j; zero where no interface
  Eigen::VectorXi faces;

  TrialResult operator()(const Eigen::VectorXd& r) const {
    const int n = static_cast<int>(r.size());
    TrialResult t;
    t.dT_K = Eigen::MatrixXd::Zero(n, 1);
    t.node_faces_after.resize(n);
    for (int i = 0; i < n; ++i) {
      t.dT_K(i, 0) = s_K[i] * r[i] * r[i];
      for (int j = 0; j < n; ++j) t.dT_K(i, 0) += pair_K(i, j) * r[i] * r[j];
      t.node_faces_after[i] = std::max(1, static_cast<int>(std::lround(faces[i] * (1.0 - r[i]))));
    }
    t.node_max_abs_dT_K = t.dT_K.col(0).cwiseAbs();
    t.max_abs_dT_K = t.node_max_abs_dT_K.maxCoeff();
    t.faces_after = t.node_faces_after.sum();
    return t;
  }
};

// Six nodes of 200 faces; 0-1, 2-3 and 4-5 share interfaces with a strong interaction.
Interacting six_nodes() {
  Interacting m;
  m.s_K = Eigen::VectorXd::Constant(6, 0.2);
  m.pair_K = Eigen::MatrixXd::Zero(6, 6);
  for (int i : {0, 2, 4}) m.pair_K(i, i + 1) = m.pair_K(i + 1, i) = 0.6;
  m.faces = Eigen::VectorXi::Constant(6, 200);
  return m;
}

std::vector<const SensitivityCurve*> pointers(const std::vector<SensitivityCurve>& curves, int n) {
  std::vector<const SensitivityCurve*> p(n, nullptr);
  for (const SensitivityCurve& c : curves) p[c.node] = &c;
  return p;
}

}  // namespace

TEST(AnchoredSuperposition, exact_at_its_anchor_and_plain_superposition_from_the_unreduced_model) {
  const Interacting m = six_nodes();
  const auto curves = sensitivity_analysis(6, m, SensitivityOptions{});
  const auto p = pointers(curves, 6);
  ASSERT_TRUE(has_difference_fields(p));
  Eigen::VectorXd a(6);
  a << 0.5, 0.5, 0.2, 0.0, 0.4, 0.0;
  const MeasuredCandidate anchor{a, m(a).dT_K};
  EXPECT_TRUE(anchored_field(p, anchor, a).isApprox(m(a).dT_K));
  const MeasuredCandidate unreduced{Eigen::VectorXd::Zero(6), Eigen::MatrixXd::Zero(6, 1)};
  EXPECT_NEAR(anchored_field(p, unreduced, a).cwiseAbs().maxCoeff(), superposed_max_abs_dT_K(p, a), 1e-12);
  // Moving node 2 from 0.2 to 0.4: the anchor keeps the 0-1 interaction that plain
  // superposition misses (0.15 K on cells 0 and 1), so it is nearer the measurement.
  Eigen::VectorXd r = a;
  r[2] = 0.4;
  const double measured = m(r).max_abs_dT_K;
  const double anchored = anchored_field(p, anchor, r).cwiseAbs().maxCoeff();
  EXPECT_LT(std::abs(anchored - measured), std::abs(superposed_max_abs_dT_K(p, r) - measured));
  EXPECT_NEAR(anchored, measured, 1e-9);  // node 2 shares its interface with 3, unreduced here
}

TEST(AnchoredSuperposition, the_path_keeps_its_prediction_within_the_target_and_respects_ceilings) {
  const Interacting m = six_nodes();
  const auto curves = sensitivity_analysis(6, m, SensitivityOptions{});
  const auto p = pointers(curves, 6);
  const MeasuredCandidate unreduced{Eigen::VectorXd::Zero(6), Eigen::MatrixXd::Zero(6, 1)};
  Eigen::VectorXd ceiling = Eigen::VectorXd::Constant(6, 1.0);
  ceiling[5] = 0.0;
  const AllocationPath path = anchored_path(p, unreduced, 0.3, 4, ceiling);
  ASSERT_FALSE(path.steps.empty());
  for (std::size_t j = 0; j < path.steps.size(); ++j) {
    EXPECT_LE(path.steps[j].predicted_K, 0.3);
    EXPECT_NE(path.steps[j].node, 5);
    EXPECT_GT(path.steps[j].to, path.steps[j].from);
  }
  const Eigen::VectorXd end = path.ratios_after(unreduced.ratios, static_cast<int>(path.steps.size()));
  EXPECT_NEAR(superposed_max_abs_dT_K(p, end), path.steps.back().predicted_K, 1e-12);
  EXPECT_GT(path.faces_removed(static_cast<int>(path.steps.size())), 0.0);
}

TEST(AnchoredSuperposition, a_step_of_one_collapse_is_not_split_into_shares_of_its_field) {
  // Node 0: 10 faces, one collapse (10 -> 8 faces at 0.25) moves the model by 1 K, as NPP_16's
  // small nodes do; the decimator reaches a ratio between 0 and 0.25 by that same collapse or
  // not at all. Node 1: 200 faces, a smooth curve. With 4 subdivisions node 0 may step to its
  // sample only, node 1 anywhere on the grid.
  SensitivityCurve small{0, {0.25}, {1.0}, {8}, {Eigen::MatrixXd::Constant(2, 1, 0.0)}};
  small.dT_K[0](0, 0) = 1.0;
  SensitivityCurve big{1, {0.5}, {0.2}, {100}, {Eigen::MatrixXd::Constant(2, 1, 0.0)}};
  big.dT_K[0](1, 0) = 0.2;
  const std::vector<const SensitivityCurve*> p{&small, &big};
  const MeasuredCandidate unreduced{Eigen::VectorXd::Zero(2), Eigen::MatrixXd::Zero(2, 1)};
  const AllocationPath path = anchored_path(p, unreduced, 0.5, 4, Eigen::VectorXd::Constant(2, 1.0));
  ASSERT_FALSE(path.steps.empty());
  for (const PathStep& s : path.steps) EXPECT_NE(s.node, 0);  // its only step costs 1 K > 0.5 K
  EXPECT_NEAR(path.steps.back().to, 0.5, 1e-12);
  EXPECT_EQ(path.steps.size(), 4u);  // 100 faces in 4 substeps of 25
}

TEST(CombinedPush, learns_an_interaction_the_single_node_fields_miss_and_stays_within_the_tolerance) {
  // Node 1 alone is harmless (0.02 K at 0.3), but with node 0 reduced to 0.5 it adds 0.6 r0 r1
  // to cells 0 and 1: the path from the start candidate steps it first (cheapest by its own
  // field) and fails; the push caps it and spends the slack elsewhere, within the tolerance.
  Interacting m = six_nodes();
  const auto curves = sensitivity_analysis(6, m, SensitivityOptions{});
  const auto p = pointers(curves, 6);
  Eigen::VectorXd start = Eigen::VectorXd::Zero(6);
  start[0] = 0.5;
  TrialResult res = m(start);
  std::vector<std::pair<double, double>> predicted_measured;
  int rejected = 0, trials = 0;
  CombinedPushOptions o;
  o.tolerance_K = 0.25;
  o.max_trials = 8;
  auto counted = [&](const Eigen::VectorXd& r) { ++trials; return m(r); };
  auto record = [&](const Eigen::VectorXd&, const TrialResult& t, const std::string& action, double predicted) {
    predicted_measured.emplace_back(predicted, t.max_abs_dT_K);
    rejected += action.find("rejected") != std::string::npos;
  };
  std::vector<bool> capped;
  const Eigen::VectorXd out = combined_push(p, counted, o, record, start, res, &capped);
  ASSERT_EQ(capped.size(), 6u);
  EXPECT_LE(trials, o.max_trials);
  EXPECT_GT(rejected, 0) << "the interaction must make a planned step fail for this test";
  EXPECT_LE(res.max_abs_dT_K, o.tolerance_K);
  EXPECT_EQ(res.max_abs_dT_K, m(out).max_abs_dT_K);
  EXPECT_LT(m(out).faces_after, m(start).faces_after);  // it still reduced further
  for (int k = 0; k < 6; ++k) EXPECT_GE(out[k], start[k]);
}

TEST(CombinedPush, reduces_further_than_the_one_node_push_on_interacting_nodes) {
  // The whole informed strategy, with and without the combined push (the same trials for the
  // sweep and the start): both verified within the tolerance, the combined push fewer faces.
  const Interacting m = six_nodes();
  const auto curves = sensitivity_analysis(6, m, SensitivityOptions{});
  int faces[2] = {0, 0};
  for (int combined : {0, 1}) {
    InformedOptions io;
    io.tolerance_K = 0.5;
    io.parallel = false;
    io.start_by_superposition = true;
    io.max_combined_push_trials = combined ? 8 : 0;
    io.max_push_trials = 4;
    const ReductionOutcome out = informed_reduction(curves, 6, m, m, io);
    EXPECT_LE(out.verified.max_abs_dT_K, 0.5);
    faces[combined] = out.verified.faces_after;
    int combined_steps = 0;
    for (const auto& h : out.history) combined_steps += h.action.rfind("combined push", 0) == 0;
    EXPECT_EQ(combined_steps > 0, combined == 1);
  }
  EXPECT_LT(faces[1], faces[0]);
}

TEST(CombinedPush, splits_a_step_that_fails_on_its_own_before_capping_its_node) {
  // Node 0: 400 faces, alone 0.1 K at 0.5 and 0.2 K at 0.8 on its own cell; beside the rest of
  // the model, past ratio 0.7 it adds 0.5 K to cell 1 (a neighbour its single-node trials never
  // moved). The grid steps of 30 faces between 0.5 and 0.8 put 0.7 inside the step from 0.65 to
  // 0.725, which fails alone; its halves are measured down to the grid's resolution, so the node
  // stops between 0.65 and 0.7 instead of at 0.65.
  SensitivityCurve c{0, {0.5, 0.8}, {0.1, 0.2}, {200, 80}, {Eigen::MatrixXd::Zero(2, 1), Eigen::MatrixXd::Zero(2, 1)}};
  c.dT_K[0](0, 0) = 0.1;
  c.dT_K[1](0, 0) = 0.2;
  const std::vector<const SensitivityCurve*> p{&c, nullptr};
  int trials = 0;
  auto trial = [&](const Eigen::VectorXd& r) {
    ++trials;
    TrialResult t;
    t.dT_K = Eigen::MatrixXd::Zero(2, 1);
    t.dT_K(0, 0) = r[0] <= 0.5 ? 0.2 * r[0] : 0.1 + (r[0] - 0.5) / 3.0;
    if (r[0] > 0.7) t.dT_K(1, 0) = 0.5;
    t.node_max_abs_dT_K = t.dT_K.col(0).cwiseAbs();
    t.max_abs_dT_K = t.node_max_abs_dT_K.maxCoeff();
    t.node_faces_after = Eigen::VectorXi::Constant(2, 10);
    t.node_faces_after[0] = static_cast<int>(std::lround(400.0 * (1.0 - r[0])));
    t.faces_after = t.node_faces_after.sum();
    return t;
  };
  Eigen::VectorXd start(2);
  start << 0.5, 0.0;
  TrialResult res = trial(start);
  std::vector<std::string> actions;
  auto record = [&](const Eigen::VectorXd&, const TrialResult&, const std::string& a, double) { actions.push_back(a); };
  CombinedPushOptions o;
  o.tolerance_K = 0.3;
  o.max_trials = 8;
  trials = 0;
  std::vector<bool> capped;
  const Eigen::VectorXd out = combined_push(p, trial, o, record, start, res, &capped);
  EXPECT_LE(trials, o.max_trials);
  EXPECT_TRUE(capped[0]);
  EXPECT_GT(out[0], 0.65 + 1e-9) << "the failed step's passing half was not taken";
  EXPECT_LE(out[0], 0.7);
  EXPECT_LE(res.max_abs_dT_K, o.tolerance_K);
  EXPECT_EQ(res.max_abs_dT_K, trial(out).max_abs_dT_K);
  int halves = 0;
  for (const auto& a : actions) halves += a.find("half of its failed step") != std::string::npos;
  EXPECT_GE(halves, 1);
}

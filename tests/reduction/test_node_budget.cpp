// Per-original-node budgets of a merged model's decimation (reduction/node_budget.h), plain data.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>

#include "thermodec/common/errors.h"
#include "thermodec/reduction/node_budget.h"

using namespace thermodec;

namespace {

// Original a, b, c, d; merged: "ab" (a + b), "c", "d". Two output times.
struct Case {
  SimulationResult original, merged;
  std::vector<std::pair<std::string, std::string>> map{{"d", "d"}, {"a", "ab"}, {"b", "ab"}, {"c", "c"}};
  Case() {
    original.nodes = {"a", "b", "c", "d"};
    original.temperature_K.resize(4, 2);
    original.temperature_K << 300.0, 301.0,  //
        300.4, 300.8,                         //
        250.0, 250.0,                         //
        200.0, 200.0;
    merged.nodes = {"ab", "c", "d"};
    merged.temperature_K.resize(3, 2);
    merged.temperature_K << 300.2, 300.9,  //
        250.0, 250.0,                       //
        200.1, 200.0;
  }
};

}  // namespace

TEST(NodeBudget, each_original_node_keeps_the_search_tolerance_less_its_merge_difference) {
  const Case k;
  const double s = 0.5;
  const NodeBudget b = node_budget(k.original, k.merged, k.map, s);
  ASSERT_EQ(b.merged_row, (std::vector<int>{0, 0, 1, 2}));
  // a: |300.2 - 300| = 0.2, |300.9 - 301| = 0.1; b: 0.2, 0.1; c: 0; d: 0.1, 0.
  EXPECT_NEAR(b.weight(0, 0), s / (s - 0.2), 1e-9);
  EXPECT_NEAR(b.weight(0, 1), s / (s - 0.1), 1e-9);
  EXPECT_NEAR(b.weight(1, 0), s / (s - 0.2), 1e-9);
  EXPECT_NEAR(b.weight(2, 0), 1.0, 1e-12);
  EXPECT_NEAR(b.weight(3, 0), s / (s - 0.1), 1e-9);
  EXPECT_NEAR(b.weight(3, 1), 1.0, 1e-12);
  // A merge over the tolerance: the node keeps the floor share, weight 1 / floor_share.
  Case far = k;
  far.merged.temperature_K(0, 0) = 301.0;
  EXPECT_NEAR(node_budget(far.original, far.merged, far.map, s, 0.1).weight(0, 0), 10.0, 1e-9);
}

TEST(NodeBudget, a_scaled_trial_within_the_search_tolerance_stays_within_it_against_the_original) {
  const Case k;
  const double s = 0.5;
  const NodeBudget b = node_budget(k.original, k.merged, k.map, s, 0.05, true);
  TrialResult t;
  t.dT_K.resize(3, 2);
  t.dT_K << 0.25, -0.3,  //
      -0.45, 0.1,         //
      0.2, 0.49;
  t.node_max_abs_dT_K = t.dT_K.cwiseAbs().rowwise().maxCoeff();
  t.max_abs_dT_K = t.dT_K.cwiseAbs().maxCoeff();
  t.faces_after = 7;
  const TrialResult w = within_node_budget(t, b);
  ASSERT_EQ(w.dT_K.rows(), 4);
  ASSERT_EQ(w.node_max_abs_dT_K.size(), 3);
  EXPECT_EQ(w.faces_after, 7);
  // Merged node ab: e_a = +0.2 / -0.1, e_b = -0.2 / +0.1 (t0 / t1). 0.25 at t0 moves a further
  // from its original (s - 0.2 left) and b towards its own (s + 0.2); -0.3 at t1 moves a away
  // (s - 0.1 left) and b towards (s + 0.1).
  EXPECT_NEAR(w.dT_K(0, 0), 0.25 * s / 0.3, 1e-9);
  EXPECT_NEAR(w.dT_K(1, 0), 0.25 * s / 0.7, 1e-9);
  EXPECT_NEAR(w.dT_K(0, 1), -0.3 * s / 0.4, 1e-9);
  EXPECT_NEAR(w.dT_K(1, 1), -0.3 * s / 0.6, 1e-9);
  EXPECT_NEAR(w.node_max_abs_dT_K[0], std::max(0.25 / 0.3, 0.3 / 0.4) * s, 1e-9);
  EXPECT_NEAR(w.node_max_abs_dT_K[1], 0.45, 1e-12);  // c: no merge, weight 1
  // d: e = +0.1 at t0, and 0.2 moves it further (s - 0.1 left); e = 0 at t1.
  EXPECT_NEAR(w.node_max_abs_dT_K[2], std::max(0.2 * s / 0.4, 0.49), 1e-9);
  EXPECT_NEAR(w.max_abs_dT_K, w.node_max_abs_dT_K.maxCoeff(), 1e-12);
  // Whatever the trial, scaled within s means every original node within s of the original.
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 2; ++j) {
      const int m = b.merged_row[i];
      const double against_original = t.dT_K(m, j) + k.merged.temperature_K(m, j) - k.original.temperature_K(i, j);
      if (std::abs(w.dT_K(i, j)) <= s) EXPECT_LE(std::abs(against_original), s + 1e-9);
    }
  // Linear on each side of zero: fields of one sign superpose exactly.
  TrialResult half = t;
  half.dT_K *= 0.5;
  TrialResult sum = t;
  sum.dT_K += half.dT_K;
  EXPECT_TRUE(within_node_budget(sum, b).dT_K.isApprox(w.dT_K + within_node_budget(half, b).dT_K, 1e-12));
}

TEST(NodeBudget, a_difference_towards_the_original_may_reach_it_and_pass_it_by_the_tolerance) {
  const Case k;
  const double s = 0.5;
  const NodeBudget b = node_budget(k.original, k.merged, k.map, s, 0.05, true);
  // ab sits 0.2 K above a at t0: moving it down by up to s + 0.2 = 0.7 K keeps a within s of
  // its original; moving it up, only s - 0.2. b (0.2 K below ab) the other way round.
  EXPECT_NEAR(b.opposite_weight(0, 0), s / 0.7, 1e-9);
  EXPECT_NEAR(b.merge_dT_K(0, 0), 0.2, 1e-9);
  TrialResult t;
  t.dT_K = Eigen::MatrixXd::Zero(3, 2);
  t.dT_K(0, 0) = -0.69;
  const TrialResult down = within_node_budget(t, b);
  EXPECT_NEAR(down.dT_K(0, 0), -0.69 * s / 0.7, 1e-9);
  EXPECT_LE(std::abs(down.dT_K(0, 0)), s);
  EXPECT_LE(std::abs(-0.69 + 0.2), s);    // a against its original
  EXPECT_GT(std::abs(down.dT_K(1, 0)), s);  // b: 0.89 K below its original
  t.dT_K(0, 0) = 0.31;                    // up: a 0.51 K from its original
  EXPECT_GT(std::abs(within_node_budget(t, b).dT_K(0, 0)), s);
  // Random fields: scaled within s means within s of the original, every node and time.
  std::uint64_t x = 12345;
  auto uniform = [&] { x = x * 6364136223846793005ULL + 1442695040888963407ULL; return double(x >> 11) * 0x1.0p-53; };
  for (int r = 0; r < 2000; ++r) {
    for (int m = 0; m < 3; ++m)
      for (int j = 0; j < 2; ++j) t.dT_K(m, j) = (2.0 * uniform() - 1.0);
    const TrialResult w = within_node_budget(t, b);
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 2; ++j) {
        const int m = b.merged_row[i];
        const double against_original = t.dT_K(m, j) + k.merged.temperature_K(m, j) - k.original.temperature_K(i, j);
        if (std::abs(w.dT_K(i, j)) <= s) EXPECT_LE(std::abs(against_original), s + 1e-9);
      }
  }
  // Without signed budgets (the default) a difference either way is charged alike.
  const NodeBudget unsigned_b = node_budget(k.original, k.merged, k.map, s);
  EXPECT_TRUE(unsigned_b.opposite_weight.isApprox(unsigned_b.weight, 1e-12));
  t.dT_K(0, 0) = -0.69;
  EXPECT_NEAR(within_node_budget(t, unsigned_b).dT_K(0, 0), -0.69 * s / 0.3, 1e-9);
}

TEST(NodeBudget, nan_fails_and_bad_shapes_are_refused) {
  const Case k;
  const NodeBudget b = node_budget(k.original, k.merged, k.map, 0.5);
  TrialResult t;
  t.dT_K = Eigen::MatrixXd::Zero(3, 2);
  t.dT_K(1, 1) = std::numeric_limits<double>::quiet_NaN();
  const TrialResult w = within_node_budget(t, b);
  EXPECT_TRUE(std::isnan(w.max_abs_dT_K));
  EXPECT_TRUE(std::isnan(w.node_max_abs_dT_K[1]));
  EXPECT_EQ(w.node_max_abs_dT_K[0], 0.0);
  t.dT_K = Eigen::MatrixXd::Zero(3, 3);
  EXPECT_THROW(within_node_budget(t, b), InvalidInput);
  Case bad = k;
  bad.map.pop_back();  // c unmapped
  EXPECT_THROW(node_budget(bad.original, bad.merged, bad.map, 0.5), InvalidInput);
  EXPECT_THROW(node_budget(k.original, k.merged, k.map, 0.0), InvalidInput);
}

// Lower bounds on node merging (reduction/merge_bound.h) against cases counted by hand and
// against brute force over every partition of a small network.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>

#include "thermodec/reduction/merge_bound.h"

using namespace thermodec;

namespace {

// Nodes at constant temperatures (one case, two times).
Eigen::MatrixXd constant_temperatures(const std::vector<double>& T_K) {
  Eigen::MatrixXd t(static_cast<Eigen::Index>(T_K.size()), 2);
  for (std::size_t i = 0; i < T_K.size(); ++i) t.row(static_cast<Eigen::Index>(i)).setConstant(T_K[i]);
  return t;
}

// The fewest groups of pairwise spread <= 2 tol, by trying every assignment (small n only).
int fewest_groups_brute_force(const Eigen::MatrixXd& spread, double tol) {
  const int n = static_cast<int>(spread.rows());
  std::vector<int> group(n, 0);
  int best = n;
  std::function<void(int, int)> place = [&](int i, int groups) {
    if (groups >= best) return;
    if (i == n) { best = groups; return; }
    for (int g = 0; g <= groups; ++g) {
      bool fits = true;
      for (int k = 0; k < i && fits; ++k) fits = group[k] != g || spread(i, k) <= 2.0 * tol;
      if (!fits) continue;
      group[i] = g;
      place(i + 1, std::max(groups, g + 1));
    }
  };
  place(0, 0);
  return best;
}

}  // namespace

TEST(MergeBound, nodes_farther_apart_than_twice_the_tolerance_each_need_their_own_merged_node) {
  // 0, 0.4, 0.8, 1.2, 1.6 K: at 0.5 K tolerance (1 K spread) {0, 1.2} and {0.4, 1.6} are apart,
  // so 2 merged nodes at least ({0, 0.4, 0.8} and {1.2, 1.6} reach it).
  const Eigen::MatrixXd s = pairwise_spread_K({constant_temperatures({0.0, 0.4, 0.8, 1.2, 1.6})});
  EXPECT_NEAR(s(0, 4), 1.6, 1e-12);
  EXPECT_EQ(nodes_pairwise_apart(s, 0.5).size(), 2u);
  EXPECT_EQ(nodes_pairwise_apart(s, 0.1).size(), 5u);
  EXPECT_EQ(nodes_pairwise_apart(s, 1.0).size(), 1u);
  // Three nodes would need every member within 0.4 K of its merged node, one 0.2 K, five none.
  EXPECT_NEAR(least_merge_dT_K(s, 2), 0.4, 1e-12);
  EXPECT_NEAR(least_merge_dT_K(s, 3), 0.2, 1e-12);
  EXPECT_NEAR(least_merge_dT_K(s, 1), 0.8, 1e-12);
  EXPECT_EQ(least_merge_dT_K(s, 5), 0.0);
}

TEST(MergeBound, the_spread_is_the_largest_over_cases_and_times_and_never_merged_nodes_stand_alone) {
  Eigen::MatrixXd a(2, 3), b(2, 3);
  a << 300, 301, 302, 300, 300, 300;  // 2 K apart at the last time
  b << 250, 250, 250, 253, 250, 250;  // 3 K apart at the first time of the second case
  const Eigen::MatrixXd s = pairwise_spread_K({a, b});
  EXPECT_NEAR(s(0, 1), 3.0, 1e-12);
  const Eigen::MatrixXd kept = pairwise_spread_K({constant_temperatures({1.0, 1.0, 1.0})}, {2});
  EXPECT_TRUE(std::isinf(kept(0, 2)));
  EXPECT_EQ(nodes_pairwise_apart(kept, 10.0).size(), 2u);  // {0, 1} merged, node 2 alone
  EXPECT_TRUE(std::isinf(least_merge_dT_K(kept, 1)));
}

TEST(MergeBound, the_bound_never_exceeds_the_fewest_groups_found_by_brute_force) {
  // Random temperature histories of 9 nodes: the clique bound is a lower bound on the exact
  // minimum partition (and equals it on these interval-like data more often than not).
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.0, 1.0);
  int equal = 0;
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::MatrixXd t(9, 6);
    for (Eigen::Index i = 0; i < t.rows(); ++i)
      for (Eigen::Index k = 0; k < t.cols(); ++k) t(i, k) = 280.0 + g(rng);
    const Eigen::MatrixXd s = pairwise_spread_K({t});
    for (double tol : {0.5, 1.0, 1.5}) {
      const int bound = static_cast<int>(nodes_pairwise_apart(s, tol).size());
      const int exact = fewest_groups_brute_force(s, tol);
      EXPECT_LE(bound, exact) << "trial " << trial << " tol " << tol;
      equal += bound == exact;
    }
  }
  EXPECT_GE(equal, 30);  // of 60
}

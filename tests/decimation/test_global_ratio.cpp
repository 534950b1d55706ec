#include <gtest/gtest.h>

#include "thermodec/common/errors.h"
#include "thermodec/decimation/global_ratio.h"

using namespace thermodec;

namespace {
double removed(const Eigen::VectorXi& counts, const Eigen::VectorXd& ratio) {
  return (counts.cast<double>().array() * ratio.array()).sum();
}
}  // namespace

TEST(GlobalRatio, every_node_gets_the_global_ratio_when_none_saturates) {
  Eigen::VectorXi counts(3);
  counts << 40, 10, 20;
  const Eigen::VectorXd r = node_ratios_for_global_ratio(counts, 0.5);
  for (int i = 0; i < 3; ++i) EXPECT_DOUBLE_EQ(r[i], 0.5);
}

TEST(GlobalRatio, one_facet_node_carries_its_deficit_to_the_next_smallest) {
  Eigen::VectorXi counts(3);
  counts << 100, 1, 10;  // visiting order: 1, 10, 100
  const Eigen::VectorXd r = node_ratios_for_global_ratio(counts, 0.5);
  EXPECT_DOUBLE_EQ(r[1], 0.0);              // cannot lose its only facet
  EXPECT_DOUBLE_EQ(r[2], (5.0 + 0.5) / 10);  // its own 5 plus the carried 0.5
  EXPECT_DOUBLE_EQ(r[0], 0.5);
  EXPECT_DOUBLE_EQ(removed(counts, r), 0.5 * 111);
}

TEST(GlobalRatio, deficit_cascades_through_saturated_nodes) {
  Eigen::VectorXi counts(4);
  counts << 2, 2, 3, 100;
  // min 1 face each: the three small nodes can lose 1, 1, 2; at ratio 0.9 they want 1.8, 1.8, 2.7.
  const Eigen::VectorXd r = node_ratios_for_global_ratio(counts, 0.9);
  EXPECT_DOUBLE_EQ(r[0], 0.5);
  EXPECT_DOUBLE_EQ(r[1], 0.5);
  EXPECT_DOUBLE_EQ(r[2], 2.0 / 3.0);
  EXPECT_NEAR(removed(counts, r), 0.9 * 107, 1e-9);
  EXPECT_LT(r[3], 1.0);
}

TEST(GlobalRatio, ties_are_visited_in_node_order_and_caps_are_respected) {
  Eigen::VectorXi counts(3);
  counts << 10, 10, 10;
  Eigen::VectorXd cap(3);
  cap << 0.1, 1.0, 1.0;
  const Eigen::VectorXd r = node_ratios_for_global_ratio(counts, 0.5, 1, cap);
  EXPECT_DOUBLE_EQ(r[0], 0.1);
  EXPECT_DOUBLE_EQ(r[1], 0.9);  // node 1 comes before node 2 and absorbs the 4-face deficit
  EXPECT_DOUBLE_EQ(r[2], 0.5);
  EXPECT_DOUBLE_EQ(removed(counts, r), 15.0);
}

TEST(GlobalRatio, unreachable_global_ratio_saturates_every_node) {
  Eigen::VectorXi counts(2);
  counts << 1, 2;
  const Eigen::VectorXd r = node_ratios_for_global_ratio(counts, 0.9);
  EXPECT_DOUBLE_EQ(r[0], 0.0);
  EXPECT_DOUBLE_EQ(r[1], 0.5);
}

TEST(GlobalRatio, invalid_arguments_throw) {
  Eigen::VectorXi counts(2);
  counts << 1, 2;
  EXPECT_THROW(node_ratios_for_global_ratio(counts, 1.0), InvalidInput);
  EXPECT_THROW(node_ratios_for_global_ratio(counts, -0.1), InvalidInput);
  EXPECT_THROW(node_ratios_for_global_ratio(counts, 0.5, 1, Eigen::VectorXd::Ones(3)), InvalidInput);
  counts[0] = -1;
  EXPECT_THROW(node_ratios_for_global_ratio(counts, 0.5), InvalidInput);
}

// Combined node reductions predicted by superposing single-node difference fields: the
// allocation respects its target on the superposed field, and differences of opposite sign
// cancel where the per-node curves (max |dT| alone) would add up.
#include <gtest/gtest.h>

#include <cmath>

#include "thermodec/reduction/superposition.h"

using namespace thermodec;

namespace {

// A node's curve whose field at ratio r is r * shape (one row per node, two output times).
SensitivityCurve linear_curve(int node, const Eigen::MatrixXd& shape, int faces) {
  SensitivityCurve c;
  c.node = node;
  for (double r : {0.25, 0.5, 0.75}) {
    c.ratios.push_back(r);
    c.dT_K.push_back(r * shape);
    c.max_abs_dT_K.push_back(r * shape.cwiseAbs().maxCoeff());
    c.faces_after.push_back(static_cast<int>(std::lround(faces * (1.0 - r))));
  }
  return c;
}

std::vector<const SensitivityCurve*> pointers(const std::vector<SensitivityCurve>& curves) {
  std::vector<const SensitivityCurve*> p;
  for (const SensitivityCurve& c : curves) p.push_back(&c);
  return p;
}

}  // namespace

TEST(Superposition, field_interpolates_between_samples_and_is_zero_unreduced) {
  Eigen::MatrixXd shape(2, 2);
  shape << 1.0, -2.0, 0.5, 0.0;
  const SensitivityCurve c = linear_curve(0, shape, 100);
  EXPECT_DOUBLE_EQ(difference_field_at(c, 0.0).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_TRUE(difference_field_at(c, 0.375).isApprox(0.375 * shape));
  EXPECT_TRUE(difference_field_at(c, 0.125).isApprox(0.125 * shape));  // towards zero at r = 0
  EXPECT_TRUE(difference_field_at(c, 0.9).isApprox(0.75 * shape));    // last sample beyond the sweep
}

TEST(Superposition, opposite_sign_fields_cancel) {
  Eigen::MatrixXd warm(2, 2), cool(2, 2);
  warm << 1.0, 1.0, 0.2, 0.2;
  cool = -warm;
  const std::vector<SensitivityCurve> curves{linear_curve(0, warm, 100), linear_curve(1, cool, 100)};
  const auto p = pointers(curves);
  ASSERT_TRUE(has_difference_fields(p));
  EXPECT_NEAR(superposed_max_abs_dT_K(p, Eigen::Vector2d(0.75, 0.75)), 0.0, 1e-12);
  EXPECT_NEAR(superposed_max_abs_dT_K(p, Eigen::Vector2d(0.75, 0.25)), 0.5, 1e-12);
  // Each node alone moves the model by 0.75 K at 0.75: a per-node budget of 0.3 K stops
  // both at 0.25, the superposition takes both to their last sample.
  const Eigen::VectorXd r = superposed_allocation(p, 2, 0.3);
  EXPECT_DOUBLE_EQ(r[0], 0.75);
  EXPECT_DOUBLE_EQ(r[1], 0.75);
}

TEST(Superposition, allocation_stays_within_target_and_prefers_cheap_faces) {
  Eigen::MatrixXd a(3, 2), b(3, 2), c(3, 2);
  a << 0.02, 0.01, 0.0, 0.0, 0.01, 0.0;  // insensitive, 400 faces
  b << 0.4, 0.1, 0.3, 0.0, 0.0, 0.2;     // medium, 300 faces
  c << 4.0, 2.0, 1.0, 3.0, 0.0, 1.0;     // sensitive, 300 faces
  const std::vector<SensitivityCurve> curves{linear_curve(0, a, 400), linear_curve(1, b, 300),
                                             linear_curve(2, c, 300)};
  const auto p = pointers(curves);
  for (double target : {0.05, 0.2, 0.5, 1.0}) {
    const Eigen::VectorXd r = superposed_allocation(p, 3, target);
    EXPECT_LE(superposed_max_abs_dT_K(p, r), target + 1e-12) << target;
    EXPECT_DOUBLE_EQ(r[0], 0.75) << target;  // the insensitive node always goes furthest
    EXPECT_LE(r[2], r[1]) << target;
  }
  EXPECT_DOUBLE_EQ(superposed_allocation(p, 3, 1e-6).maxCoeff(), 0.0);  // nothing fits
}

TEST(Superposition, nan_field_is_never_chosen) {
  Eigen::MatrixXd shape(1, 1);
  shape << 0.1;
  std::vector<SensitivityCurve> curves{linear_curve(0, shape, 10)};
  curves[0].dT_K[1](0, 0) = std::nan("");
  const auto p = pointers(curves);
  EXPECT_DOUBLE_EQ(superposed_allocation(p, 1, 10.0)[0], 0.25);
  EXPECT_TRUE(std::isnan(superposed_max_abs_dT_K(p, Eigen::VectorXd::Constant(1, 0.5))));
}

TEST(Superposition, curves_without_fields_are_reported) {
  SensitivityCurve c;
  c.ratios = {0.5};
  c.max_abs_dT_K = {0.1};
  c.faces_after = {5};
  const std::vector<const SensitivityCurve*> p{&c};
  EXPECT_FALSE(has_difference_fields(p));
  EXPECT_TRUE(std::isnan(superposed_max_abs_dT_K(p, Eigen::VectorXd::Constant(1, 0.5))));
}

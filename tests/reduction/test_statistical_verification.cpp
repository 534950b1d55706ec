// The statistical tolerance guarantee: a bound on the true max |dT| from replicate pairs.
#include <gtest/gtest.h>

#include <random>

#include "thermodec/reduction/statistical_verification.h"

using namespace thermodec;

namespace {

// Replicate differences of a synthetic reduction: a true difference D (nodes x times) plus
// independent Gaussian noise of standard deviation sigma per cell, as two independent seeds give.
std::vector<Eigen::MatrixXd> draws(const Eigen::MatrixXd& D, double sigma, int R, std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, sigma);
  std::vector<Eigen::MatrixXd> out;
  for (int j = 0; j < R; ++j) out.push_back(D.unaryExpr([&](double x) { return x + g(rng); }));
  return out;
}

Eigen::MatrixXd true_difference(double peak_K) {
  Eigen::MatrixXd D = Eigen::MatrixXd::Constant(20, 60, 0.2 * peak_K);
  D(7, 33) = peak_K;  // the node and time where the reduction moves the model most
  return D;
}

}  // namespace

TEST(StatisticalVerification, a_lucky_single_draw_under_the_tolerance_is_rejected_when_the_truth_is_above) {
  const double tol = 0.05, sigma = 0.004;
  const Eigen::MatrixXd D = true_difference(0.053);  // truly beyond the tolerance
  std::mt19937_64 rng(7);
  // The search keeps whichever single draw the noise favoured: the best of 200 is under tol.
  double best = 1e9;
  for (int k = 0; k < 200; ++k) {
    const Eigen::MatrixXd d = draws(D, sigma, 1, rng).front();
    const double m = d.cwiseAbs().maxCoeff();
    if (m < best) best = m;
  }
  ASSERT_LT(best, tol) << "the synthetic search must find a draw that looks acceptable";
  // The guarantee, with fresh replicates, rejects it; over many verifications, at least the
  // confidence level of them (97.5 %, here with a generous allowance for 400 trials).
  int rejected = 0;
  const int runs = 400;
  for (int k = 0; k < runs; ++k) rejected += !difference_upper_bound(draws(D, sigma, 4, rng)).accepts(tol);
  EXPECT_GE(rejected, static_cast<int>(0.95 * runs));
}

TEST(StatisticalVerification, the_upper_bound_covers_the_true_maximum_at_its_confidence) {
  const double sigma = 0.01;
  const Eigen::MatrixXd D = true_difference(0.03);
  std::mt19937_64 rng(11);
  int covered = 0;
  const int runs = 1000;
  for (int k = 0; k < runs; ++k) covered += difference_upper_bound(draws(D, sigma, 4, rng)).upper_bound_K >= 0.03;
  // Binomial: 1000 x 0.975 = 975 with sd 5; the max over cells only adds coverage.
  EXPECT_GE(covered, 960);
}

TEST(StatisticalVerification, a_candidate_well_within_the_tolerance_is_accepted) {
  std::mt19937_64 rng(3);
  const VerificationStatistics s = difference_upper_bound(draws(true_difference(0.02), 0.004, 4, rng));
  EXPECT_TRUE(s.accepts(0.05)) << s.upper_bound_K;
  EXPECT_NEAR(s.max_abs_dT_K, 0.02, 0.015);
  EXPECT_GT(s.standard_error_K, 0.0);
}

TEST(StatisticalVerification, student_t_quantiles_match_the_tables) {
  EXPECT_NEAR(student_t_975(3), 3.182, 1e-3);
  EXPECT_NEAR(student_t_975(30), 2.042, 1e-3);
  EXPECT_NEAR(student_t_975(60), 2.000, 2e-3);
  EXPECT_NEAR(student_t_975(1000), 1.962, 1e-3);
}

TEST(StatisticalVerification, verification_seeds_avoid_the_search_seeds) {
  const auto s = verification_seeds(1, 4);
  ASSERT_EQ(s.size(), 4u);
  for (auto x : s) EXPECT_GT(x - 1, std::uint64_t(1) << 20);
}

#pragma once
//! The tolerance guarantee in statistical terms: the reduced model's true max |dT| against the
//! original, bounded from above at a stated confidence from replicate simulations with seeds
//! that no step of the search used.
//!
//! Estimator (docs/reduction.md, "Verification"). R replicate pairs j: the original and the
//! candidate both simulated with seed s_j (every seed fresh, one per pair), so faces the
//! decimation left alone trace the same rays in both (correlated sampling, as in the search) and
//! the pair's difference carries only the noise of what changed. The pairs are independent of
//! each other: per node i and time k, the differences d_j(i, k) are independent draws whose
//! mean is the true difference D(i, k) = E[T_candidate] - E[T_original]; their
//! mean m and standard error se = sd / sqrt(R) give the one-sided Student-t bound
//! |m| + t(conf, R - 1) se, which exceeds |D(i, k)| with probability >= conf. The bound on
//! max_{i,k} |D| is the max over (i, k) of those bounds: at the cell (i*, k*) where the true
//! maximum sits, the cell's own bound covers it with probability >= conf, and the max over cells
//! is at least that bound, so no correction for the number of cells is needed (a bound on a
//! maximum; it is conservative elsewhere). The point estimate max |m| is biased upwards by the
//! noise (a max over many noisy cells), so it is reported but never used to accept.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace thermodec {

constexpr double kVerificationConfidence = 0.975;  //!< one-sided level of the upper bound

struct VerificationStatistics {
  double max_abs_dT_K = 0.0;      //!< estimate: max over nodes/times of |mean pair difference|
  double standard_error_K = 0.0;  //!< standard error of the mean at that node/time
  double upper_bound_K = 0.0;     //!< max over nodes/times of |mean| + t se
  double confidence = kVerificationConfidence;
  int replicates = 0;             //!< pairs R
  std::vector<std::uint64_t> seeds;  //!< s_0, s_1, ...: pair j simulates both models with s_j
  int node = -1;                  //!< row of the upper bound's cell (of the stacked matrices)
  int time_index = -1;            //!< its column
  bool accepts(double tolerance_K) const { return upper_bound_K <= tolerance_K; }  //!< NaN fails
};

//! One-sided Student-t quantile t(0.975, dof) for dof >= 1 (table to 30, then the
//! Cornish-Fisher expansion). \throw InvalidInput if dof < 1.
double student_t_975(int dof);

//! Statistics of R >= 2 replicate difference matrices (candidate - original, same shape; rows
//! nodes, columns times; several load cases may be stacked as extra rows).
//! \throw InvalidInput if fewer than 2 replicates or shapes differ.
VerificationStatistics difference_upper_bound(const std::vector<Eigen::MatrixXd>& replicate_dT_K);

//! Seeds of R verification pairs (one per pair), disjoint from `search_seed` + [0, 2^20) (the
//! reference, its noise-floor runs and every trial salt are derived from the search seed that way).
std::vector<std::uint64_t> verification_seeds(std::uint64_t search_seed, int replicates);

}  // namespace thermodec

#include "thermodec/nodes/thermal_model.h"
#include "thermodec/thermal/simulate_model.h"

namespace thermodec {

//! One load case to verify: the original model and the candidate (same nodes, same times).
struct VerificationCase {
  const ThermalModel* original = nullptr;
  const ThermalModel* candidate = nullptr;
  //! A merged candidate: its results are compared through its node_map (one row per original
  //! node), and the original is sampled as densely as the merged node each of its nodes is in.
  bool through_node_map = false;
};

//! The original's verification runs, kept between verifications of several candidates of one
//! reduction: per case, the results for seeds s_0, s_1, ... (filled on first use).
struct VerificationOriginals {
  std::vector<std::vector<SimulationResult>> per_case;
};

//! Simulates every case's original and candidate with seed s_j for j < replicates
//! (verification_seeds(search_seed, replicates)), full simulations (nothing reused between
//! runs), and bounds the max |dT| over cases, nodes and times (difference_upper_bound, cases
//! stacked as rows). Cost: 2 x replicates simulations per case, replicates when `originals`
//! already holds the original's runs (a later candidate of the same reduction).
//! \throw InvalidInput if replicates < 2 or a case's results do not line up.
VerificationStatistics verify_statistically(const std::vector<VerificationCase>& cases,
                                            const ModelSimulationSettings& settings, int replicates,
                                            std::uint64_t search_seed, VerificationOriginals* originals = nullptr);

}  // namespace thermodec

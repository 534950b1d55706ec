#pragma once
//! Superposition anchored on a measured combined candidate. Plain superposition
//! (superposition.h) predicts a combination of node reductions from the unreduced model:
//!   dT(r) ~= sum_k dT_k(r_k),
//! and misses every interaction between the nodes (shared interfaces, strong radiative
//! couplings): on NPP_16 at 0.5 K a push predicted 0.35 K measured 0.58 K. Anchored on a
//! candidate a whose combined field F(a) was measured, the prediction keeps every interaction
//! already present in a and superposes only what changes:
//!   dT(r) ~= F(a) + sum_{k: r_k != a_k} (dT_k(r_k) - dT_k(a_k)),
//! which is exact for r = a and equals plain superposition for the unreduced anchor (F = 0).
//! The combined push (combined_push.h) plans on it and learns the interactions of what it
//! changes from its own combined measurements.
#include <Eigen/Core>
#include <vector>

#include "thermodec/reduction/sensitivity.h"

namespace thermodec {

//! A candidate whose combined trial was measured: its ratios and signed difference field [K]
//! (nodes x output times, TrialResult::dT_K).
struct MeasuredCandidate {
  Eigen::VectorXd ratios;
  Eigen::MatrixXd dT_K;
};

//! F(anchor) + sum over nodes whose ratio differs of dT_k(r_k) - dT_k(anchor_k) [K]; nodes
//! without a curve contribute nothing.
//! \pre has_difference_fields(curve_of), anchor.dT_K of the fields' shape, sizes match.
Eigen::MatrixXd anchored_field(const std::vector<const SensitivityCurve*>& curve_of, const MeasuredCandidate& anchor,
                               const Eigen::VectorXd& ratios);

//! One step of a path: node `node` from ratio `from` to `to`.
struct PathStep {
  int node = -1;
  double from = 0.0, to = 0.0;
  double faces_removed = 0.0;  //!< estimated from the curve's face counts (linear between samples)
  double predicted_K = 0.0;    //!< anchored max |dT| after this step and every earlier one [K]
};

//! A greedy path from an anchor: steps in the order taken, and the anchored field after each.
struct AllocationPath {
  std::vector<PathStep> steps;
  std::vector<Eigen::MatrixXd> field_K;  //!< field_K[j]: after steps 0..j
  //! Ratios after the first `count` steps (0 = the anchor's).
  Eigen::VectorXd ratios_after(const Eigen::VectorXd& anchor_ratios, int count) const;
  //! Estimated faces removed by the first `count` steps.
  double faces_removed(int count) const;
};

//! Greedy allocation from `anchor`, ratios only rising: each node moves on a grid of
//! `subdivisions` equal steps between consecutive samples of its curve (and from 0 to the
//! first sample), fewer where the samples are under 4 faces apart a step (down to the samples
//! alone: the decimator removes whole collapses, so a ratio between samples one collapse apart
//! takes the whole step, not the interpolated share of its field), never past its last sample
//! nor `ceiling[k]`; each step is the one that
//! removes the most estimated faces per kelvin of anchored increase among those whose anchored
//! max |dT| stays <= target_K, each increase counted as at least 5 % of the anchor's slack
//! (target_K - its max |dT|): a step predicted to cost nothing is the least known, and goes by
//! its faces. Deterministic (ties by node index). Cost: O(steps x nodes x field size).
//! \pre has_difference_fields(curve_of); subdivisions >= 1.
AllocationPath anchored_path(const std::vector<const SensitivityCurve*>& curve_of, const MeasuredCandidate& anchor,
                             double target_K, int subdivisions, const Eigen::VectorXd& ceiling);

}  // namespace thermodec

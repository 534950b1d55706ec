#pragma once
//! Combined push: spends the slack of a candidate within the tolerance on many nodes at once,
//! planned by superposition anchored on the candidate's measured field
//! (anchored_superposition.h), and learns the nodes' interactions from its own combined
//! measurements instead of trusting the single-node fields.
//!
//! A round plans the greedy path from the current candidate c (most faces per kelvin first,
//! on a grid of `subdivisions` steps between the curves' samples) up to the tolerance and
//! measures its end. If it fails, the search continues on the same path, a regula falsi on its
//! length with a field-valued interaction model: between the last passing point lo (measured
//! field F_lo) and the first failing one hi (F_hi), the interaction error the path's own
//! prediction A missed, E = (F_hi - F_lo) - (A_hi - A_lo), is taken to grow with the faces the
//! path removes, so point j is predicted as
//!   F_j ~= F_lo + (A_j - A_lo) + (s_j - s_lo) / (s_hi - s_lo) E     (s: faces removed),
//! and the farthest j the model keeps within the tolerance is measured next (E halved each time
//! lo moves again while hi stays, the Illinois rule, so it does not creep). Where no point is
//! predicted within it, the first step beyond lo alone is measured; a first step that fails alone
//! is bisected on its node's ratio down to parts of two edge collapses (4 faces; within
//! max_trials), and its node capped at the last passing ratio. A passing point becomes c, and a round ends where the path has
//! nothing left between lo and hi; the next round plans again from c (its measured field holds
//! every interaction met so far).
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "thermodec/reduction/sensitivity.h"
#include "thermodec/reduction/trial.h"

namespace thermodec {

struct CombinedPushOptions {
  double tolerance_K = 0.5;
  int max_trials = 8;    //!< combined trials, passing or not
  int subdivisions = 4;  //!< grid steps between consecutive samples of a node's curve
  //! A round whose path removes fewer than this share of the candidate's faces (and under one
  //! face) is not measured.
  double min_faces_share = 0.002;
  //! Per node, the highest ratio a path may plan (empty: each curve's last sample).
  Eigen::VectorXd ceiling;
  //! Called once, before the first trial, with the trials to expect (InformedOptions::before_push).
  std::function<void(int trials_left)> before_first_trial;
  std::function<void(const std::string&)> log;
};

//! Records a measured step: ratios, trial, action, and the prediction that chose it [K].
using PredictedRecordFn =
    std::function<void(const Eigen::VectorXd&, const TrialResult&, const std::string&, double predicted_K)>;

//! From `start` (its trial in `result`, within the tolerance, with a difference field), the
//! farthest candidate the combined push measured within the tolerance; `result` receives its
//! trial. Returns `start` unchanged if the curves or the trial carry no fields. `capped`, if
//! given, receives per node whether a step of it failed on its own (it went no further).
//! Deterministic.
Eigen::VectorXd combined_push(const std::vector<const SensitivityCurve*>& curve_of, const TrialFunction& trial,
                              const CombinedPushOptions& options, const PredictedRecordFn& record,
                              const Eigen::VectorXd& start, TrialResult& result, std::vector<bool>* capped = nullptr);

}  // namespace thermodec

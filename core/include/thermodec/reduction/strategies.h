#pragma once
//! Reduction strategies over a TrialFunction: the paper's physics-unaware uniform loop (§IV)
//! and the physics-informed prediction (§V), extended with measured back-off and push.
#include <Eigen/Core>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "thermodec/reduction/sensitivity.h"
#include "thermodec/reduction/trial.h"

namespace thermodec {

//! One evaluated candidate, in the order evaluated.
struct ReductionStep {
  Eigen::VectorXd ratio_per_node;
  TrialResult result;
  bool within_tolerance = false;
  std::string action;  //!< "uniform 0.45", "predicted", "back off node 3", "push node 5", "verify"
  //! Informed: the superposition's prediction of max |dT| for this candidate [K]
  //! (superposition.h); NaN when the curves carry no difference fields.
  double predicted_K = std::numeric_limits<double>::quiet_NaN();
  //! Combined push: the prediction that chose this candidate [K], superposition anchored on the
  //! measured candidate it started from, with the interactions learnt on its path
  //! (combined_push.h); NaN for other steps.
  double anchored_predicted_K = std::numeric_limits<double>::quiet_NaN();
};

struct ReductionOutcome {
  Eigen::VectorXd ratio_per_node;   //!< the returned candidate's ratios
  TrialResult verified;             //!< its confirming evaluation by `verify` (always <= tolerance)
  std::vector<ReductionStep> history;
  //! Informed: the first predicted candidate, before correction, back-off and push (by
  //! superposition when the curves carry difference fields, else the paper's per-node one).
  Eigen::VectorXd predicted_ratio_per_node;
};

struct UniformOptions {
  double tolerance_K = 0.5;
  double step = 0.05;        //!< global ratio increment per iteration
  double max_ratio = 0.98;
  int bisection_steps = 3;   //!< refine between the last ratio within tolerance and the first beyond
  std::function<void(const std::string&)> log;
};

//! §IV: one global ratio for every node (mapped to per-node ratios by `ratios_for_global`,
//! e.g. the deficit rule), raised step by step with a trial each time until max |dT| exceeds
//! the tolerance; returns the last candidate within it, confirmed by `verify`.
//! \throw InvalidInput if tolerance_K <= 0 or step not in (0, 1).
ReductionOutcome uniform_reduction(
    const std::function<Eigen::VectorXd(double global_ratio)>& ratios_for_global,
    const TrialFunction& trial, const TrialFunction& verify, const UniformOptions& options);

struct InformedOptions {
  double tolerance_K = 0.5;
  int max_evaluations = 80;   //!< bound on trials after the prediction (back-off + push); once
                              //!< spent while backing off, every node's share of the tolerance
                              //!< on its own curve is scaled back (bisection, 6 trials per pass)
  //! Leave-one-out trials per back-off step: when more nodes are reduced, only this many are
  //! measured, those most suspect of the excess: first the nodes below the fewest faces any
  //! of their own samples kept, then by the largest of the node's own curve at its ratio and
  //! its own |dT| in the failing candidate. 0 = every reduced node (a step on a CAD
  //! model with 64 nodes otherwise costs 64 trials, ~45-75 min).
  int max_leave_one_out = 16;
  //! A leave-one-out step whose best back-off removes less than this share of the excess
  //! (max|dT| - tolerance) says no single node is to blame: many nodes' allowances add up.
  //! The back-off then goes straight to the scale-back of every node's share of the tolerance
  //! instead of more steps (tdrs at 0.5 K: three steps of 8 trials took the excess from 1.06 K
  //! to 0.56 K in 28 min, the scale-back after them reached 0.33 K in 6 trials). 0 = never.
  double stall_fraction = 0.3;
  bool push = true;           //!< use remaining slack to reduce nodes further
  //! With difference fields, after the one-node push (below), the slack left is spent on many
  //! nodes at once (combined_push.h): at most this many combined trials, outside
  //! max_evaluations. 0 = one-node push only.
  int max_combined_push_trials = 8;
  //! Bound on the push's trials (within max_evaluations). On a large CAD model each push is a
  //! trial of a combined candidate, about a full simulation against the original, for one node
  //! one sample further (tdrs at 0.5 K: 6 pushes of ~21 s removed 120 of 17289 faces), unless
  //! before_push rebases the trials on the push's start candidate.
  int max_push_trials = std::numeric_limits<int>::max();
  //! Start from the superposition's allocation instead of the per-node prediction. On the
  //! sample satellite both reach the same model: decimating two nodes that share an interface
  //! is not the sum of decimating each (the shared mesh changes), so the first allocation
  //! measured 2.6 K for a predicted 0.16 K and needed a correction (docs/reduction.md).
  bool start_by_superposition = false;
  //! Superposition start: re-allocations after a predicted candidate measured over the
  //! tolerance, each with the target scaled by tolerance / measured (then back-off as above).
  int max_corrections = 2;
  //! Back-off with difference fields, when the superposition is trusted on the failing
  //! candidate (within a factor 1.5 of its measurement) and predicts that no single node's
  //! back-off brings it within the tolerance: re-allocate every node by superposition, the
  //! target scaled by tolerance / measured and corrected as above (max_corrections), instead
  //! of leave-one-out steps and the scale-back. Once per reduction; what still fails backs
  //! off as below. A first re-allocation that removes under stall_fraction of the failing
  //! candidate's excess refutes the superposition there (effects that do not add): the search
  //! returns to that candidate, uncorrected, for leave-one-out steps (no foreseen stall).
  bool reallocate_by_superposition = true;
  //! Skip the push and scale-back trials the superposition rules out: predicted max |dT|
  //! still over the tolerance after the most favourable error measured so far in the search,
  //! taken both as an offset and as a factor (strategies.cpp). They count as failed steps.
  //! Needs curves with difference fields.
  bool screen_by_superposition = true;
  bool parallel = true;       //!< leave-one-out contributions measured concurrently
  //! Called once, before the push's first trial, with the candidate the push starts from, its
  //! trial and the push trials to expect (nodes whose next or halfway step the superposition
  //! does not rule out, within the bounds): the caller may prepare cheaper trials near that
  //! candidate (ReductionReference::rebase). Trials must give the same results after it.
  std::function<void(const Eigen::VectorXd& start, const TrialResult& start_result, int trials_left)> before_push;
  //! Faces per node the decimator leaves for the given ratios (decimation only, no simulation).
  //! With it, after the combined push, the nodes at their curves' ends whose sweep stalled
  //! alone (SensitivityCurve::stalled_ratio) and whose stalled ratio removes at least 2 more of
  //! their faces in the pushed candidate (neighbours decimated) go there in one trial; if it
  //! fails, the one freeing the most faces alone (at most 2 trials). Empty: not tried.
  std::function<Eigen::VectorXi(const Eigen::VectorXd& ratios)> node_faces;
  std::function<void(const std::string&)> log;
  //! Node names for progress lines and history actions ("push antenna_dish to 0.6"); nodes
  //! without a name here are called "node <index>".
  std::vector<std::string> node_names;
};

//! §V.B and beyond. Starts from each node's feasible ratio on its own curve (the paper's
//! prediction), or, with start_by_superposition and curves that carry difference fields,
//! from the superposition's allocation (superposition.h): the greedy choice of per-node
//! ratios whose summed fields stay within the tolerance; if its trial measures more, the
//! allocation's target is scaled by tolerance / measured and re-allocated (up to
//! max_corrections trials). Every recorded step carries the superposition's prediction when
//! the curves have fields, whichever start was used. While the combined candidate exceeds the
//! tolerance (coupled nodes make the prediction optimistic): if the superposition is trusted on
//! it and predicts that no single back-off suffices, re-allocates every node by superposition
//! with a corrected target (reallocate_by_superposition, once); otherwise, or if that still
//! fails, measures each reduced node's contribution by a leave-one-out trial (the
//! max_leave_one_out most suspect ones) and backs off the largest contributor one sample on its
//! curve; once the budget is spent, or a step removed under stall_fraction of the excess (no
//! single culprit), it bisects every node's share of the tolerance. Then, while slack remains,
//! pushes nodes one sample further in order of smallest predicted increase (at most
//! max_push_trials trials), keeping only pushes that stay within tolerance; then, with
//! difference fields, the combined push (combined_push.h) from that result, at most
//! max_combined_push_trials trials. The returned
//! candidate always passed `verify`, the confirming evaluation (a full recompute, or the trial
//! itself where trials are bit-identical to one, as in reduce_model); if nothing else does, the
//! unreduced model is returned.
ReductionOutcome informed_reduction(const std::vector<SensitivityCurve>& curves, int num_nodes,
                                    const TrialFunction& trial, const TrialFunction& verify,
                                    const InformedOptions& options);

}  // namespace thermodec

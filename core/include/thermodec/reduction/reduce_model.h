#pragma once
//! The product's main job: reduce a thermal model's mesh as far as a temperature tolerance
//! allows, node by node, guided by simulation, and verify the result (paper §IV-V).
#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "thermodec/nodes/load_case.h"
#include "thermodec/reduction/node_budget.h"
#include "thermodec/reduction/node_merging.h"
#include "thermodec/reduction/reduction_reference.h"
#include "thermodec/reduction/sensitivity.h"
#include "thermodec/reduction/statistical_verification.h"
#include "thermodec/reduction/strategies.h"

namespace thermodec {

enum class ReductionStrategy { informed, uniform };

//! What a sensitivity sweep hands back to reduce_model().
struct SweepOutcome {
  std::vector<SensitivityCurve> curves;  //!< every node's curve, in node order (only where the strategy runs)
  //! This process only swept its share for another one (an MPI rank other than 0):
  //! reduce_model() returns right after the sweep with ReductionRun::sweep_only set.
  bool stop_after_sweep = false;
  int trials_elsewhere = 0;               //!< trials other processes evaluated for this sweep
  //! Largest peak resident memory of the other processes at the end of the sweep [bytes] (0: none).
  long long peak_memory_bytes_elsewhere = 0;
};

//! Performs the informed strategy's sweep: (nodes, trial, options, faces per node, trials this
//! process evaluated so far) -> outcome. Must give the curves sensitivity_analysis(nodes,
//! trial, options) gives.
using SensitivitySweep = std::function<SweepOutcome(int, const TrialFunction&, const SensitivityOptions&,
                                                    const Eigen::VectorXi&, const std::function<int()>&)>;

struct ReduceSettings {
  double tolerance_K = 0.5;  //!< max |dT| over nodes and the orbit allowed vs the reference [K]
  ReductionStrategy strategy = ReductionStrategy::informed;
  ReductionReferenceSettings reference;
  //! Its cap_K is replaced by sensitivity_cap_factor x tolerance, and refine_first_above_K is
  //! at most the tolerance.
  SensitivityOptions sensitivity;
  double sensitivity_cap_factor = 2.0;
  UniformOptions uniform;          //!< tolerance taken from tolerance_K
  InformedOptions informed;        //!< tolerance taken from tolerance_K
  int noise_runs = 2;              //!< independent-seed runs measuring the noise floor (>= 2)
  //! Replicate pairs (original, candidate) of the final statistical verification (>= 2), with
  //! seeds the search never used (reduction/statistical_verification.h).
  int verification_replicates = 4;
  //! Searches at most (the first aims below the tolerance by the noise margin; a rejected
  //! candidate widens the margin by the bound's excess); then the unreduced model.
  int verification_attempts = 3;
  //! When every attempt is rejected: at most this many more verifications of the least rejected
  //! candidate's ratios scaled towards the unreduced model (back_off_scale,
  //! reduction/verification_back_off.h), the deepest accepted one kept; 0: the unreduced model
  //! at once. (A merged model's decimation backs off: reduction/merge_reduction.h.)
  int back_off_verifications = 0;
  //! Noise-targeted sampling before anything else (thermal/simulate_model.h,
  //! decide_sampling_boosts): nodes whose estimated temperature noise exceeds this fraction of
  //! the tolerance get more samples. 0 = off; models that already carry boosts keep them.
  double noise_target_fraction = 0.05;
  //! With noise-targeted sampling on, a kind of samples (IR rays; sun and Earth samples) that
  //! every node has in far more than the target needs is divided by a common power of two (at
  //! least 4, at most 64; noise_targeted_thinning): a 100k-face model meshed for 4000 rays per
  //! face traces ~16x fewer rays in every simulation of the reduction. false = only boosts.
  bool thin_oversampling = true;
  //! Area drift is a bias of every decimated node, not noise: a node that keeps its heat input
  //! and radiates it away (sigma eps A T^4 fixed) moves by dT = -T dA / (4 A). The decimator's
  //! area bound (reference.decimation.max_relative_area_change) is lowered, if needed, to
  //! 4 area_error_fraction tolerance / T_max (T_max: the hottest node of any case's reference)
  //! so that area drift alone costs at most this fraction of the tolerance. 0 = keep the bound.
  //! 0.1 (docs/benchmarks.md, measured against 0.2 and none): 0.2 reduces the sample and NPP_16
  //! a little further (a tighter bound cuts the decimator's reach on CAD nodes), but on tdrs
  //! the drift of 34 reduced nodes adds up (combined prediction 1.20 K instead of 0.55 K).
  double area_error_fraction = 0.1;
  //! With area_error_fraction > 0: the same share of the tolerance against each node's own
  //! first-order sensitivity to its area (reduction/area_bounds.h) instead of T_max / 4 for
  //! every node, at most the decimator's own bound. A node in radiative balance with its
  //! surroundings may then drift further than a sunlit one radiating to space.
  bool per_node_area_bound = true;
  //! Extra trials for the predicted-vs-real plot: targets as multiples of the search tolerance
  //! (the tolerance less the verification margin), so that the 1.0 point is the informed
  //! search's first candidate, already simulated. Each other point is a trial of a combined
  //! candidate, about a whole simulation on a large model (tdrs: 4 points, 67 s), so the
  //! budgets for models over kBareMeshCoarseSweepFaces faces keep the 1.0 point alone; the
  //! plot still shows every candidate the search measured against its prediction.
  std::vector<double> prediction_targets{0.1, 0.25, 0.5, 1.0, 2.0};
  //! Further load cases the reduced model must also meet (hot and cold cases, ...): the
  //! model's own environment is the first case; each extra one gets its own reference,
  //! noise floor and incremental trials, and every trial and verification takes the largest
  //! |dT| over all cases. Costs about one reduction's simulations per case. Names must differ
  //! from each other and from "model" (the model's own case), else InvalidInput.
  std::vector<LoadCase> extra_cases;
  std::function<void(const std::string&)> progress;  //!< human-readable progress lines
  //! The sensitivity sweep; empty: sensitivity_analysis in this process. mpi_sweep() spreads
  //! it over MPI ranks (reduction/mpi_sweep.h, when built with MPI).
  SensitivitySweep sweep;
  //! The statistical verification of a candidate (one model per load case, in case order);
  //! empty: verify_statistically against the references' models. A reduction of merged nodes
  //! verifies against the unmerged original through the node map instead
  //! (reduction/merge_reduction.h).
  std::function<VerificationStatistics(const std::vector<const ThermalModel*>&)> verify_candidate;
  //! The bound the verification must meet [K]; <= 0: tolerance_K. (A merged model's decimation
  //! searches within what the merges left of the tolerance and is verified against the whole.)
  double verification_tolerance_K = 0.0;
  //! Per load case (index, the case's reference, the search tolerance S [K] before any widened
  //! margin), the per-original-node budget its trials are scaled by (reduction/node_budget.h);
  //! empty: trials as measured. A merged model's decimation measures its trials against the
  //! unmerged original's nodes this way (reduction/merge_reduction.h).
  std::function<NodeBudget(std::size_t, const SimulationResult&, double)> node_budget;
};

struct NodeReduction {
  std::string name;
  int faces_before = 0, faces_after = 0;
  double requested_ratio = 0.0;   //!< ratio asked of the decimator
  double ratio = 0.0;             //!< achieved: 1 - faces_after / faces_before
  double predicted_ratio = 0.0;   //!< informed: the paper's prediction from the curve alone
  double max_abs_dT_K = 0.0;      //!< this node's max |dT| over the orbit in the verified model
  double area_before_m2 = 0.0, area_after_m2 = 0.0;
  //! Reach: faces the requested ratio asked to keep, and, when the decimator ended above
  //! that, what refused the node's remaining edges (NodeDecimationStats::blocked_edges, by
  //! collapse_block_name) and the most frequent reason ("none" when the target was reached).
  int target_faces = 0;
  std::string stopped_by = "none";
  std::vector<std::pair<std::string, int>> blocked_edges;
};

struct PredictionPoint {
  double target_K = 0.0;     //!< tolerance the prediction was made for
  double predicted_K = 0.0;  //!< largest single-node difference on the curves at those ratios
  double real_K = 0.0;       //!< simulated difference of all nodes reduced together
  int faces_after = 0;
};

//! What the verified reduced model gives in one load case.
struct CaseResult {
  std::string name;
  double noise_floor_K = 0.0;                 //!< that case's independent-seed noise floor
  //! Ray records its reference kept (IR + sun/Earth) and its share of the record budget, which
  //! the cases split equally [bytes].
  std::size_t ray_record_bytes = 0, ray_record_budget_bytes = 0;
  //! What its reference keeps outside the budget (RecordUse): face-level view factors and the
  //! Earth rays' hits [bytes].
  std::size_t view_factor_bytes = 0, earth_hit_bytes = 0;
  double max_temperature_difference_K = 0.0;  //!< reduced vs reference, full recompute [K]
  std::string max_difference_node;
  double max_difference_time_s = 0.0;
};

struct ReductionRun {
  std::string strategy;
  double tolerance_K = 0.0;
  double noise_floor_K = 0.0;     //!< max |dT| between independent-seed reference runs (max over cases)
  //! The decimator's bound on each node's relative area change used by every trial (see
  //! ReduceSettings::area_error_fraction) [-].
  double max_relative_area_change = 0.0;
  //! Per node, the bound actually used (ReduceSettings::per_node_area_bound); empty when every
  //! node has max_relative_area_change [-].
  std::vector<double> node_max_relative_area_change;
  int faces_before = 0, faces_after = 0;
  double max_temperature_difference_K = 0.0;  //!< of the verified reduced model (full recompute; max over cases)
  std::string max_difference_node;
  std::string max_difference_case;            //!< load case where it occurs ("model": the model's own)
  double max_difference_time_s = 0.0;
  std::vector<NodeReduction> nodes;
  std::vector<SensitivityCurve> curves;       //!< informed only
  std::vector<PredictionPoint> prediction;    //!< informed only
  ReductionOutcome outcome;
  std::vector<CaseResult> cases;              //!< the model's own case first, then extra_cases
  Candidate reduced;                          //!< the verified reduced model and its result (own case)
  SimulationResult reference;                 //!< own case
  Mesh reference_mesh;                         //!< the input mesh (for pictures)
  int trials = 0;
  //! What the loader's bare-mesh cleanup changed (ThermalModel::mesh_cleanup), if it ran.
  std::optional<BareMeshCleanupReport> mesh_cleanup;
  int rays_per_face = 0;       //!< IR rays per face side used (model.radiation)
  int sun_rays_per_face = 0;   //!< shadow samples per face side used
  //! Node::sampling_boost of every node (1 = not boosted), as the reduced model keeps them.
  std::vector<Node::SamplingBoost> sampling_boost;
  double seconds_total = 0.0, seconds_noise = 0.0, seconds_sensitivity = 0.0, seconds_search = 0.0;
  //! The returned model's statistical verification (accepted: upper_bound_K <= tolerance_K).
  VerificationStatistics verification;
  double search_tolerance_K = 0.0;  //!< the tolerance the accepted search aimed at (tol - margin)
  double seconds_verification = 0.0;
  //! Set by the front end: peak resident memory of this process (common/peak_memory.h) and
  //! the largest of the other MPI ranks' (0: single process) [bytes].
  long long peak_memory_bytes = 0, peak_memory_bytes_other_ranks = 0;
  int ranks = 1;          //!< processes the sensitivity sweep was spread over
  //! Only the sweep ran here, for another process (ReduceSettings::sweep said so): nothing
  //! else is filled and nothing is to be written.
  bool sweep_only = false;
  //! Set when nodes were merged before the decimation (reduction/merge_reduction.h).
  std::optional<NodeMerging> merging;
};

//! Bounded run time for bare meshes (ThermalModel::mesh_cleanup set; no-op otherwise): the
//! simulation ray budgets of apply_bare_mesh_ray_budgets, and above
//! kBareMeshCoarseSweepFaces faces a coarse sensitivity sweep (ratios 0.5, 0.8, 0.93: at most
//! 3 trials per node instead of 11; then 0.96, 0.98 only while a node's last sample reached its
//! face count, SensitivityOptions::ratios_beyond), at most 20 trials after the prediction, 8 leave-one-out
//! trials per back-off step, 6 push trials, and no extra predicted-vs-real trials. Measured
//! effect in docs/benchmarks.md ("Reduction: NASA meshes").
void apply_bare_mesh_reduction_budget(ThermalModel& model, ReduceSettings& settings);
constexpr int kBareMeshCoarseSweepFaces = 2000;

//! Model files (no-op for bare meshes, above) over kBareMeshCoarseSweepFaces faces: a sweep on
//! halving face counts, ratios 1 - 2^-k for k = 1..7 (a node keeps 1/2, 1/4, ... 1/128 of its
//! faces): at most 7 trials per node instead of 11, spaced where a finely meshed node's curve
//! changes (its |dT| grows with the faces removed relative to those kept), and reaching 99.2 %
//! where the fixed grid stops at 98 %. A node the decimator cannot take further ends early.
//! No extra predicted-vs-real trials either (ReduceSettings::prediction_targets), and at most
//! 40 trials after the prediction (InformedOptions::max_evaluations).
void apply_large_model_sweep(const ThermalModel& model, ReduceSettings& settings);

//! Runs the whole reduction: reference simulation, noise floor, (informed) sensitivity and
//! prediction, strategy search, full verification.
//! \throw InvalidInput if the tolerance is not finite and positive, or is below twice the
//! measured noise floor (the message says what to change); SolverError from the stages.
ReductionRun reduce_model(const ThermalModel& model, const ReduceSettings& settings);

}  // namespace thermodec

#pragma once
//! The reference side of every reduction trial: the input model, its simulation, and the
//! reusable radiative state. A trial decimates nodes by given ratios, simulates the
//! candidate and compares it with the reference. Trials depend only on this object and their
//! ratios, so they can run in parallel (TBB here; processes or machines later).
#include <Eigen/Core>
#include <memory>
#include <mutex>

#include "thermodec/decimation/decimate_nodes.h"
#include "thermodec/nodes/thermal_model.h"
#include "thermodec/reduction/trial.h"
#include "thermodec/thermal/simulate_model.h"

namespace thermodec {

//! The decimator's options in a reduction: the radiative collapse cost, which keeps fewer
//! faces than the geometric one within the same verified tolerance (docs/reduction.md), and
//! the projected-area budget (steep turns of slivers and kinked contours paid from a budget
//! equal to the node-area bound: docs/decimation.md, "Projected-area budget"), which widens
//! the decimator's reach on CAD meshes of long thin triangles, and released contacts (a flat
//! panel a sheet stands on keeps no vertex of the contact: DecimationOptions::release_contacts),
//! and the projected-area cap with node-area restoration (each node's projected area in 64
//! directions within 10 x its area bound; a collapse past the area bound runs when the node's
//! free vertices restore its area: docs/decimation.md), which reach further on curved CAD parts
//! while moving their projected areas less. The reflected-sunlight cap stays off
//! (reflection_cap 0; `reduce --reflection-cap F` passes the reference's reflected fluxes and
//! views per face: docs/decimation.md, measured on NPP_16 in docs/benchmarks.md), and so do wide
//! kinks (wide_kink_area_fraction 0; `reduce --wide-kink F`: docs/decimation.md, "Wide kinks",
//! measured on NPP_16 in docs/benchmarks.md).
inline DecimationOptions reduction_decimation_options() {
  DecimationOptions o;
  o.collapse_cost = CollapseCostKind::radiative;
  o.projected_area_budget = 1.0;
  o.release_contacts = true;
  o.near_contact_fraction = 0.05;  // docs/decimation.md, "Near contacts"
  o.projected_area_cap = 10.0;
  o.restore_node_areas = true;
  o.reflection_cap = 0.0;  // off: not yet fewer faces on NPP_16 (docs/benchmarks.md, "Reflected sunlight")
  return o;
}

struct ReductionReferenceSettings {
  DecimationOptions decimation = reduction_decimation_options();
  ModelSimulationSettings simulation;  //!< same for reference, trials and verification
  //! Memory for the reference's reusable ray records [bytes] (record_budget.h); 0 = the
  //! default (default_record_budget_bytes). Results do not depend on it, only trial speed.
  std::size_t record_budget_bytes = 0;
};

//! One evaluated candidate with everything needed to report it.
struct Candidate {
  ThermalModel model;               //!< the reference model with the decimated mesh
  DecimationResult decimation;
  SimulationResult result;
  TemperatureDifference difference;  //!< vs the reference result
  TrialResult trial;
};

//! The Monte Carlo noise a reduction trial sees. A trial redraws the samples (rays, sun and
//! Earth points) of the faces it changed and keeps every other one (correlated sampling), so
//! its noise is that of redrawing one node's samples, not of a new seed everywhere: for each
//! node, the reference with only that node's samples redrawn (Node::sampling_salt, same
//! geometry) against the reference.
struct TrialNoiseFloor {
  Eigen::VectorXd node_max_abs_dT_K;  //!< #nodes: max |dT| [K] when node k's samples are redrawn
  TemperatureDifference worst;        //!< the largest of them (node and time where it occurs)
  int worst_resampled_node = -1;      //!< whose samples were redrawn in `worst`
};

//! The reusable ray records a reference kept (record_budget.h) [bytes]. Records left out make
//! trials slower, never different.
struct RecordUse {
  std::size_t ir_bytes = 0;         //!< IR records kept (0: over their budget)
  std::size_t ir_needed_bytes = 0;  //!< what all IR records take
  std::size_t ir_budget_bytes = 0;
  std::size_t load_bytes = 0;       //!< sun and Earth records kept (0: over their budget)
  std::size_t load_budget_bytes = 0;
  bool loads_kept = false;
  //! Kept outside the record budget, whatever it is: the face-level view factors (12 bytes a
  //! non-zero entry) and the Earth rays' hits that light each side (16 bytes a hit).
  std::size_t view_factor_bytes = 0;
  std::size_t earth_hit_bytes = 0;
};

class ReductionReference {
 public:
  //! Simulates `model` fully (the reference) and prepares the reusable radiative state, in
  //! one pass (equal to simulate_model(model, settings.simulation)). `reference_result`, if
  //! given, must be that result and is used as is.
  //! \throw InvalidInput / SolverError from the stages.
  ReductionReference(const ThermalModel& model, const ReductionReferenceSettings& settings,
                     const SimulationResult* reference_result = nullptr);
  ~ReductionReference();
  ReductionReference(const ReductionReference&) = delete;
  ReductionReference& operator=(const ReductionReference&) = delete;

  const ThermalModel& model() const;
  const SimulationResult& result() const;
  //! The reference's node couplings (those its result was simulated with).
  const NodeCouplings& couplings() const;
  //! Faces per node of the reference mesh.
  const Eigen::VectorXi& faces_per_node() const;
  //! The reference's reflected sunlight per face side, its views of the nodes and the nodes'
  //! absorbed powers (DecimationOptions::reflection; empty without loads).
  const DecimationOptions::ReflectionData& reflection() const;
  //! Largest ratio each node can reach alone under the decimator's constraints.
  Eigen::VectorXd max_ratio_per_node() const;

  //! Incremental trial: reuses the reference's rays (correlated sampling, re-tracing only
  //! what the changed nodes can affect); memoised by ratios and by the candidate mesh they
  //! decimate to. Thread-safe.
  TrialResult trial(const Eigen::VectorXd& ratio_per_node) const;
  //! Full verification: the candidate simulated from scratch, nothing reused. Thread-safe.
  TrialResult verify(const Eigen::VectorXd& ratio_per_node) const;
  //! The candidate itself (decimated model + its result), incremental or full. A candidate
  //! already evaluated the same way (a trial, or a verification) is decimated again and its
  //! result taken from memory, not simulated again.
  Candidate candidate(const Eigen::VectorXd& ratio_per_node, bool full) const;

  //! Prepares a second reusable state next to the original's: the candidate of `ratio_per_node`
  //! simulated with its own ray records and load samples (`record_budget_bytes` for them, as
  //! ReductionReferenceSettings::record_budget_bytes). Every later trial whose ratios differ
  //! from these in fewer nodes than from the original's re-traces only what differs from that
  //! candidate, and is still compared with the original's result. A push that moves one node of
  //! a candidate reduced everywhere then costs about a one-node sweep trial instead of a whole
  //! simulation (tdrs: ~3 s against ~21 s). Same results (view factors and loads bit-identical
  //! to a full recompute either way); costs about one reference build and its records' memory.
  //! Not thread-safe with trials running: call it between them.
  void rebase(const Eigen::VectorXd& ratio_per_node, std::size_t record_budget_bytes);

  //! Redraws each node's samples in turn (salt `salt`, incremental evaluation, nodes in
  //! parallel) and compares with the reference. Costs about one trial per node.
  //! \throw InvalidInput if salt == 0.
  TrialNoiseFloor trial_noise_floor(std::uint64_t salt = 1) const;

  //! Replaces the decimation options of every later trial and verification (e.g. an area
  //! bound derived from the reference temperatures). \throw InvalidInput once a trial has
  //! been evaluated: memoised results would mix two decimations.
  void set_decimation_options(const DecimationOptions& options);
  const DecimationOptions& decimation_options() const;

  //! Trials evaluated so far (memoised repeats not counted: the same ratios, or other ratios
  //! that decimate to the same mesh) and their wall time [s].
  int trials_evaluated() const;
  const RecordUse& record_use() const;

 private:
  //! Simulates an already decimated candidate (decimation_s: the time it took), reusing the
  //! rays and samples of `via` (this reference or its rebased state) unless `full`.
  Candidate candidate_of(DecimationResult decimation, double decimation_s, bool full,
                         const ReductionReference& via) const;
  //! The candidate of `decimation` with its simulation `result`, compared with the reference.
  Candidate finish_candidate(DecimationResult decimation, SimulationResult result,
                             const TrialResult::Timing& timing) const;
  //! The state a trial of `ratios` re-traces least from: the rebased one if it is nearer.
  const ReductionReference& nearest(const Eigen::VectorXd& ratios) const;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

//! Per-node and total difference between a candidate result and the reference.
TrialResult trial_result(const SimulationResult& reference, const SimulationResult& candidate,
                         const DecimationResult& decimation);

}  // namespace thermodec

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

struct ReductionReferenceSettings {
  DecimationOptions decimation;
  ModelSimulationSettings simulation;  //!< same for reference, trials and verification
};

//! One evaluated candidate with everything needed to report it.
struct Candidate {
  ThermalModel model;               //!< the reference model with the decimated mesh
  DecimationResult decimation;
  SimulationResult result;
  TemperatureDifference difference;  //!< vs the reference result
  TrialResult trial;
};

class ReductionReference {
 public:
  //! Simulates `model` fully (the reference) and prepares the reusable radiative state.
  //! `reference_result`, if given, must be simulate_model(model, settings.simulation) (e.g. the
  //! first run of a noise-floor measurement) and is used instead of simulating again.
  //! \throw InvalidInput / SolverError from the stages.
  ReductionReference(const ThermalModel& model, const ReductionReferenceSettings& settings,
                     const SimulationResult* reference_result = nullptr);
  ~ReductionReference();
  ReductionReference(const ReductionReference&) = delete;
  ReductionReference& operator=(const ReductionReference&) = delete;

  const ThermalModel& model() const;
  const SimulationResult& result() const;
  //! Faces per node of the reference mesh.
  const Eigen::VectorXi& faces_per_node() const;
  //! Largest ratio each node can reach alone under the decimator's constraints.
  Eigen::VectorXd max_ratio_per_node() const;

  //! Incremental trial: reuses the reference's rays (correlated sampling, re-tracing only
  //! what the changed nodes can affect); memoised by ratios. Thread-safe.
  TrialResult trial(const Eigen::VectorXd& ratio_per_node) const;
  //! Full verification: the candidate simulated from scratch, nothing reused. Thread-safe.
  TrialResult verify(const Eigen::VectorXd& ratio_per_node) const;
  //! The candidate itself (decimated model + its result), incremental or full.
  Candidate candidate(const Eigen::VectorXd& ratio_per_node, bool full) const;

  //! Trials evaluated so far (memoised repeats not counted) and their wall time [s].
  int trials_evaluated() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

//! Per-node and total difference between a candidate result and the reference.
TrialResult trial_result(const SimulationResult& reference, const SimulationResult& candidate,
                         const DecimationResult& decimation);

}  // namespace thermodec

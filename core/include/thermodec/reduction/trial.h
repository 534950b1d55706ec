#pragma once
//! A reduction trial: decimate each node by its own ratio, simulate, and compare with the
//! reference simulation. The strategies (uniform, sensitivity, informed) only see this
//! function, so they are plain logic over it, testable with synthetic models, and trials can
//! later be spread over processes (each depends only on the reference and its ratios).
#include <Eigen/Core>
#include <functional>

namespace thermodec {

//! What one trial measured.
struct TrialResult {
  double max_abs_dT_K = 0.0;           //!< max over nodes and time of |T_candidate - T_reference| [K]
  Eigen::VectorXd node_max_abs_dT_K;   //!< per node: max over time of |dT| [K]
  Eigen::VectorXi node_faces_after;    //!< per node: faces kept by the decimator
  int faces_after = 0;                 //!< total faces of the candidate mesh
  //! The signed difference field T_candidate - T_reference [K], nodes x output times (with
  //! several load cases, the cases' columns side by side). Single-node trials keep it so that
  //! a combination of node reductions can be predicted by superposition (superposition.h).
  //! Empty when the trial function does not provide it.
  Eigen::MatrixXd dT_K;
  //! Wall time of the trial's phases [s] (for benchmarks; 0 for a phase it skipped). A full
  //! (non-incremental) simulation puts its couplings, loads and solve all in `simulation_s`.
  //! An incremental trial computes its couplings and loads side by side: their times overlap.
  //! Share of a full recompute's radiative work this trial did again: the larger of the IR rays
  //! traced again and the sides whose view-factor rows were rebuilt (1 for a full simulation, 0
  //! for an unchanged mesh). Deterministic, unlike its time, so decisions on the trials' cost
  //! (reduce_model's rebase) do not depend on machine load.
  double redone_fraction = 1.0;
  struct Timing {
    double decimation_s = 0.0, couplings_s = 0.0, loads_s = 0.0, solve_s = 0.0, simulation_s = 0.0;
  } timing;
};

//! Evaluates a candidate defined by `ratio_per_node` (fraction of each node's faces to
//! remove, in [0, 1): 0 keeps the node as is, 0.9 keeps about a tenth). Must be thread-safe
//! and deterministic: the same ratios always give the same result.
using TrialFunction = std::function<TrialResult(const Eigen::VectorXd& ratio_per_node)>;

}  // namespace thermodec

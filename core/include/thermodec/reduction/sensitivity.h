#pragma once
//! Per-node sensitivity analysis (paper §V.A): each node alone is decimated by increasing
//! ratios, the rest of the model unchanged, and the max temperature difference of the whole
//! model over the whole orbit is recorded, until it exceeds a cap.
#include <Eigen/Core>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "thermodec/reduction/trial.h"

namespace thermodec {

//! One node's curve: samples in increasing ratio order.
struct SensitivityCurve {
  int node = -1;
  std::vector<double> ratios;          //!< fraction of the node's faces removed [-]
  std::vector<double> max_abs_dT_K;    //!< max |dT| of the whole model [K]
  std::vector<int> faces_after;        //!< faces the node kept
  //! Per sample, the trial's signed difference field (TrialResult::dT_K), or empty.
  std::vector<Eigen::MatrixXd> dT_K;
  //! The ratio past the last sample whose trial kept the same faces (NaN if none): alone, the
  //! node could not go further, because its interfaces with undecimated neighbours hold it.
  //! With those neighbours decimated too it may (NPP_16's node_040: 19 faces at 0.8 and 0.93
  //! alone, 9 at 0.93 in the reduced model); the push tries it there (strategies.h).
  double stalled_ratio = std::numeric_limits<double>::quiet_NaN();
};

struct SensitivityOptions {
  //! Ratios tried in increasing order (the sweep of one node stops once the cap is exceeded).
  std::vector<double> ratios{0.2, 0.4, 0.5, 0.6, 0.7, 0.8, 0.85, 0.9, 0.93, 0.96, 0.98};
  double cap_K = 1.0;      //!< stop a node's sweep once max |dT| exceeds this [K]
  //! A node whose first ratio already moves the model by more than this [K] (`reduce` passes
  //! its tolerance) is tried at half that ratio, then half again, up to `halvings_below_first`
  //! times or until a trial is within it: on a coarse sweep (0.5, 0.8, 0.93 on big bare meshes)
  //! a sensitive node would otherwise be left unreduced. Off (+inf) by default.
  double refine_first_above_K = std::numeric_limits<double>::infinity();
  int halvings_below_first = 2;
  //! Ratios past the last of `ratios`, tried only while the node's previous sample reached its
  //! face count, lround(faces_before (1 - ratio)) + 1 or fewer (a collapse removes two faces),
  //! within the cap: a node that the
  //! grid's end stopped, not the decimator nor the temperatures, is swept on (a coarse sweep
  //! ends at 0.93 where the fine one goes on to 0.96, 0.98). Needs `node_faces_before`.
  std::vector<double> ratios_beyond;
  //! Faces of each node before decimation (by node index), for `ratios_beyond`; empty: off.
  std::vector<int> node_faces_before;
  bool parallel = true;    //!< nodes swept concurrently (TBB); results independent of it
  //! Called after each node's sweep: (nodes done, nodes total). Thread-safe calls.
  std::function<void(int, int)> progress;
};

//! Sweeps each node in `nodes` (all nodes if empty) over options.ratios.
//! A node whose decimator cannot go further (faces_after stops decreasing) ends its sweep; a
//! node beyond options.refine_first_above_K at the first ratio gets smaller ratios first.
//! \throw InvalidInput if ratios are not increasing within [0, 1) or cap_K <= 0.
std::vector<SensitivityCurve> sensitivity_analysis(int num_nodes, const TrialFunction& trial,
                                                   const SensitivityOptions& options,
                                                   const std::vector<int>& nodes = {});

}  // namespace thermodec

#include "thermodec/reduction/combined_push.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "thermodec/reduction/anchored_superposition.h"
#include "thermodec/reduction/superposition.h"

namespace thermodec {

namespace {

bool within(const TrialResult& r, double tol) { return r.max_abs_dT_K <= tol; }  // NaN fails

double max_abs(const Eigen::MatrixXd& s) {
  if (s.array().isNaN().any()) return std::numeric_limits<double>::quiet_NaN();
  return s.size() ? s.cwiseAbs().maxCoeff() : 0.0;
}

// One round's state on its path: the last passing point lo and the first failing one hi
// (hi = -1 before any failure), with their measured fields.
struct Bracket {
  int lo = 0, hi = -1;
  Eigen::MatrixXd field_lo, field_hi;
  //! Weight of the interaction error, halved each time lo moves again while hi stays (the
  //! Illinois rule: a plain regula falsi creeps towards a fixed end by a step or two a trial).
  double error_weight = 1.0;
  bool lo_moved_last = false;
};

// The path's anchored field after `count` steps (the anchor's own for 0).
const Eigen::MatrixXd& path_field(const AllocationPath& p, const Eigen::MatrixXd& anchor, int count) {
  return count == 0 ? anchor : p.field_K[count - 1];
}

// The farthest point strictly between lo and hi that the interaction model keeps within `tol`
// (-1 if none), with its predicted max |dT| in `predicted`.
int farthest_within(const AllocationPath& p, const Eigen::MatrixXd& anchor, const Bracket& b, double tol,
                    double& predicted) {
  const Eigen::MatrixXd& a_lo = path_field(p, anchor, b.lo);
  const Eigen::MatrixXd error =
      b.error_weight * ((b.field_hi - b.field_lo) - (path_field(p, anchor, b.hi) - a_lo));
  const double s_lo = p.faces_removed(b.lo), span = p.faces_removed(b.hi) - s_lo;
  for (int j = b.hi - 1; j > b.lo; --j) {
    const double w = span > 0.0 ? (p.faces_removed(j) - s_lo) / span : 1.0;
    const double m = max_abs(b.field_lo + (path_field(p, anchor, j) - a_lo) + w * error);
    if (m <= tol) {
      predicted = m;
      return j;
    }
  }
  return -1;
}

// The trial's line: how many nodes and steps, the nodes moved (index and ratio, the first
// few), and where a rejected trial measured its max |dT| (index of the hottest node).
std::string describe(const AllocationPath& p, const Eigen::VectorXd& from, const Eigen::VectorXd& to, int count,
                     const TrialResult& t, bool passed) {
  constexpr int kListed = 6;
  int nodes = 0;
  std::string moved;
  for (Eigen::Index k = 0; k < from.size(); ++k) {
    if (!(std::abs(to[k] - from[k]) > 1e-9)) continue;
    if (++nodes > kListed) continue;
    moved += fmt::format("{}{} -> {:.3f}", moved.empty() ? "" : ", ", k, to[k]);
  }
  if (nodes > kListed) moved += ", ...";
  std::string out = fmt::format("combined push: {} node(s), {} of the path's {} steps (~{:.0f} faces; nodes {})", nodes,
                                count, p.steps.size(), p.faces_removed(count), moved);
  Eigen::Index hottest = -1;
  if (!passed && t.node_max_abs_dT_K.size() > 0 && !t.node_max_abs_dT_K.hasNaN())
    t.node_max_abs_dT_K.maxCoeff(&hottest);
  if (hottest >= 0) out += " (max at node " + std::to_string(hottest) + ")";
  return out;
}

// Faces a part of a split step must remove to be measured on its own: two interior edge
// collapses, the grid's own resolution (anchored_superposition.h: the decimator removes whole
// collapses, so a finer share of a step is the same mesh as its neighbour on the grid).
constexpr double kLeastSplitFaces = 4.0;

// A path step that failed on its own (field_hi measured beyond the passing field_lo, `current`
// the passing ratios, at s.from for s.node) may still hold a part that passes: a grid step
// spans up to a quarter of the interval between two samples (NPP_16: node_038 from 0.725 to
// 0.8, 24 of its 93 faces, over the tolerance by a neighbour's 0.13 K). The step is bisected on
// its ratio while the interval between the last passing and the first failing ratio removes at
// least two least parts' faces and trials remain; a passing part moves `current` and
// `result`. Returns the node's last passing ratio (s.from if no part passed): its ceiling.
double split_failed_step(const PathStep& s, Eigen::MatrixXd field_lo, Eigen::MatrixXd field_hi,
                         const TrialFunction& trial, double tol, int max_trials, int& trials,
                         const PredictedRecordFn& record, Eigen::VectorXd& current, TrialResult& result) {
  const double faces_per_ratio = s.to > s.from ? s.faces_removed / (s.to - s.from) : 0.0;
  double lo = s.from, hi = s.to;
  while (trials < max_trials && faces_per_ratio * (hi - lo) >= 2.0 * kLeastSplitFaces) {
    const double mid = 0.5 * (lo + hi);
    Eigen::VectorXd r = current;
    r[s.node] = mid;
    // Measured at both ends: the field between them taken as linear in the ratio.
    const double predicted = max_abs(0.5 * (field_lo + field_hi));
    const TrialResult t = trial(r);
    ++trials;
    const bool passed = within(t, tol);
    std::string action = fmt::format("combined push: node {} to {:.4f}, half of its failed step to {:.4f} (~{:.0f} faces)",
                                     s.node, mid, hi, faces_per_ratio * (mid - s.from));
    Eigen::Index hottest = -1;
    if (!passed && t.node_max_abs_dT_K.size() > 0 && !t.node_max_abs_dT_K.hasNaN())
      t.node_max_abs_dT_K.maxCoeff(&hottest);
    if (hottest >= 0) action += " (max at node " + std::to_string(hottest) + ")";
    record(r, t, action + (passed ? "" : " (rejected: over the tolerance)"), predicted);
    if (passed) {
      lo = mid;
      field_lo = t.dT_K;
      current = r;
      result = t;
    } else {
      hi = mid;
      field_hi = t.dT_K;
    }
  }
  return lo;
}

}  // namespace

Eigen::VectorXd combined_push(const std::vector<const SensitivityCurve*>& curve_of, const TrialFunction& trial,
                              const CombinedPushOptions& o, const PredictedRecordFn& record,
                              const Eigen::VectorXd& start, TrialResult& result, std::vector<bool>* capped) {
  auto log = [&](const std::string& s) { if (o.log) o.log(s); };
  const double tol = o.tolerance_K;
  const int n = static_cast<int>(curve_of.size());
  Eigen::VectorXd current = start;
  if (capped) capped->assign(n, false);
  if (o.max_trials < 1 || !has_difference_fields(curve_of)) return current;
  for (const SensitivityCurve* c : curve_of)
    if (c && (c->dT_K.front().rows() != result.dT_K.rows() || c->dT_K.front().cols() != result.dT_K.cols()))
      return current;  // the trial carries no field of the curves' shape
  Eigen::VectorXd ceiling = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity());
  if (o.ceiling.size() == n) ceiling = o.ceiling;
  int trials = 0;
  bool announced = false;
  while (trials < o.max_trials) {
    const MeasuredCandidate anchor{current, result.dT_K};
    const AllocationPath path = anchored_path(curve_of, anchor, tol, o.subdivisions, ceiling);
    const int m = static_cast<int>(path.steps.size());
    if (m == 0 || path.faces_removed(m) < std::max(1.0, o.min_faces_share * result.faces_after)) break;
    Bracket b;
    b.field_lo = anchor.dT_K;
    int j = m;
    double predicted = path.steps.back().predicted_K;
    while (trials < o.max_trials) {
      if (!announced && o.before_first_trial) o.before_first_trial(o.max_trials - trials);
      announced = true;
      const Eigen::VectorXd r = path.ratios_after(anchor.ratios, j);
      const TrialResult t = trial(r);
      ++trials;
      const bool passed = within(t, tol);
      record(r, t, describe(path, current, r, j, t, passed) + (passed ? "" : " (rejected: over the tolerance)"),
             predicted);
      if (passed) {
        if (b.lo_moved_last) b.error_weight *= 0.5;
        b.lo_moved_last = true;
        b.lo = j;
        b.field_lo = t.dT_K;
        current = r;
        result = t;
      } else {
        b.hi = j;
        b.field_hi = t.dT_K;
        b.error_weight = 1.0;
        b.lo_moved_last = false;
      }
      if (b.hi < 0 || b.hi == b.lo + 1) {
        if (b.hi == b.lo + 1) {  // the first step beyond lo fails alone: split it, then cap its node
          const PathStep& s = path.steps[b.lo];
          const double stop =
              split_failed_step(s, b.field_lo, b.field_hi, trial, tol, o.max_trials, trials, record, current, result);
          ceiling[s.node] = stop;
          if (capped) (*capped)[s.node] = true;
          log("combined push: the step of node " + std::to_string(s.node) + " fails on its own; it stays at " +
              std::to_string(stop));
        }
        break;  // the path passed to its end, or nothing is left between lo and hi: plan again
      }
      j = farthest_within(path, anchor.dT_K, b, tol, predicted);
      if (j < 0) {  // none predicted within: measure the first step beyond lo on its own
        j = b.lo + 1;
        predicted = max_abs(b.field_lo + path_field(path, anchor.dT_K, j) - path_field(path, anchor.dT_K, b.lo));
      }
    }
  }
  return current;
}

}  // namespace thermodec

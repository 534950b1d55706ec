#include "thermodec/reduction/anchored_superposition.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "thermodec/reduction/superposition.h"

namespace thermodec {

namespace {

constexpr double kSame = 1e-9;  // ratios closer than this are the same
constexpr double kUnknownShare = 0.05;  // least charge of a step, as a share of the anchor's slack

// max |S| with NaN propagated (a NaN field fails every target).
double max_abs(const Eigen::MatrixXd& s) {
  if (s.size() == 0) return 0.0;
  if (s.array().isNaN().any()) return std::numeric_limits<double>::quiet_NaN();
  return s.cwiseAbs().maxCoeff();
}

// Faces node k keeps at `ratio`, linear between the curve's samples from its full count at 0
// (estimated from the first sample); by the ratio (100 faces a unit) where a trial did not say.
double faces_at(const SensitivityCurve& c, double ratio) {
  if (c.faces_after.empty() || c.faces_after.front() < 0) return 100.0 * (1.0 - ratio);
  double r0 = 0.0, f0 = c.faces_after.front() / std::max(1e-9, 1.0 - c.ratios.front());
  for (std::size_t i = 0; i < c.ratios.size(); ++i) {
    if (c.faces_after[i] < 0) return 100.0 * (1.0 - ratio);
    const double r1 = c.ratios[i], f1 = c.faces_after[i];
    if (ratio <= r1 + kSame) {
      const double t = r1 > r0 ? std::clamp((ratio - r0) / (r1 - r0), 0.0, 1.0) : 1.0;
      return f0 + t * (f1 - f0);
    }
    r0 = r1;
    f0 = f1;
  }
  return f0;
}

// Faces removed on the curve between consecutive samples for a substep of the grid to
// mean what the interpolated field says. The decimator reaches its target face count
// lround(N (1 - r)) by whole edge collapses (two faces each inside a node), so a ratio between
// two samples that differ by one collapse is not part of that collapse: it is all of it or
// none, and its field is the sample's, not a fraction of it. (NPP_16 at 0.5 K: 10-16-face
// nodes whose one collapse moves the model by 1.1-1.8 K, planned at a quarter of that step
// and 0.3 K, made combined pushes of ~11 faces measure 1.32 K against an anchored 0.48 K.)
constexpr double kFacesPerSubstep = 4.0;  // two interior edge collapses

// The grid of ratios a node may step to: up to `sub` equal steps between consecutive samples
// (and from 0 to the first), fewer where the samples are fewer than kFacesPerSubstep faces
// apart per step, down to the samples alone; `sub` steps where the curve has no face counts.
std::vector<double> grid_of(const SensitivityCurve& c, int sub) {
  std::vector<double> g;
  double r0 = 0.0, f0 = -1.0;
  if (!c.faces_after.empty() && c.faces_after.front() >= 0)
    f0 = c.faces_after.front() / std::max(1e-9, 1.0 - c.ratios.front());
  for (std::size_t i = 0; i < c.ratios.size(); ++i) {
    const double r1 = c.ratios[i];
    const double f1 = i < c.faces_after.size() ? c.faces_after[i] : -1.0;
    int steps = sub;
    if (f0 >= 0.0 && f1 >= 0.0)
      steps = std::clamp(static_cast<int>(std::floor((f0 - f1) / kFacesPerSubstep)), 1, sub);
    for (int s = 1; s <= steps; ++s) g.push_back(r0 + (r1 - r0) * s / steps);
    r0 = r1;
    f0 = f1;
  }
  return g;
}

}  // namespace

Eigen::MatrixXd anchored_field(const std::vector<const SensitivityCurve*>& curve_of, const MeasuredCandidate& anchor,
                               const Eigen::VectorXd& ratios) {
  Eigen::MatrixXd f = anchor.dT_K;
  for (std::size_t k = 0; k < curve_of.size() && k < static_cast<std::size_t>(ratios.size()); ++k) {
    if (!curve_of[k] || std::abs(ratios[k] - anchor.ratios[k]) <= kSame) continue;
    f += difference_field_at(*curve_of[k], ratios[k]) - difference_field_at(*curve_of[k], anchor.ratios[k]);
  }
  return f;
}

Eigen::VectorXd AllocationPath::ratios_after(const Eigen::VectorXd& anchor_ratios, int count) const {
  Eigen::VectorXd r = anchor_ratios;
  for (int j = 0; j < count && j < static_cast<int>(steps.size()); ++j) r[steps[j].node] = steps[j].to;
  return r;
}

double AllocationPath::faces_removed(int count) const {
  double s = 0.0;
  for (int j = 0; j < count && j < static_cast<int>(steps.size()); ++j) s += steps[j].faces_removed;
  return s;
}

AllocationPath anchored_path(const std::vector<const SensitivityCurve*>& curve_of, const MeasuredCandidate& anchor,
                             double target_K, int subdivisions, const Eigen::VectorXd& ceiling) {
  AllocationPath path;
  const int n = static_cast<int>(curve_of.size());
  std::vector<std::vector<double>> grid(n);
  std::vector<std::vector<Eigen::MatrixXd>> field(n);  // the node's field at each grid ratio
  std::vector<int> at(n, -1);                          // last grid index at or below the node's ratio
  std::vector<Eigen::MatrixXd> own(n);                 // the node's field at its current ratio
  for (int k = 0; k < n; ++k) {
    if (!curve_of[k]) continue;
    grid[k] = grid_of(*curve_of[k], std::max(1, subdivisions));
    for (double g : grid[k]) field[k].push_back(difference_field_at(*curve_of[k], g));
    while (at[k] + 1 < static_cast<int>(grid[k].size()) && grid[k][at[k] + 1] <= anchor.ratios[k] + kSame) ++at[k];
    own[k] = difference_field_at(*curve_of[k], anchor.ratios[k]);
  }
  Eigen::VectorXd ratio = anchor.ratios;
  Eigen::MatrixXd sum = anchor.dT_K;
  double current = max_abs(sum);
  if (!std::isfinite(current)) return path;
  // A step is charged at least a share of the anchor's slack: what a single-node field says of
  // a step is least reliable where it says almost nothing (NPP_16: a 5-face node's step
  // predicted ~0 K added 0.25 K beside its neighbour), so such steps go after the ones that
  // remove many faces instead of first.
  const double floor_K = std::max(kUnknownShare * (target_K - current), 1e-9 * target_K);
  while (true) {
    int pick = -1;
    double pick_score = -1.0, pick_max = 0.0, pick_faces = 0.0;
    for (int k = 0; k < n; ++k) {
      const int next = at[k] + 1;
      if (!curve_of[k] || next >= static_cast<int>(grid[k].size())) continue;
      if (k < ceiling.size() && grid[k][next] > ceiling[k] + kSame) continue;
      const double faces = faces_at(*curve_of[k], ratio[k]) - faces_at(*curve_of[k], grid[k][next]);
      if (!(faces >= 0.5)) continue;  // removes nothing: no reason to spend anything on it
      const double m = max_abs(sum + field[k][next] - own[k]);
      if (!(m <= target_K)) continue;  // NaN or over the target
      const double score = faces / std::max(m - current, floor_K);
      if (score > pick_score) pick_score = score, pick = k, pick_max = m, pick_faces = faces;
    }
    if (pick < 0) break;
    const int next = ++at[pick];
    sum += field[pick][next] - own[pick];
    own[pick] = field[pick][next];
    path.steps.push_back({pick, ratio[pick], grid[pick][next], pick_faces, pick_max});
    path.field_K.push_back(sum);
    ratio[pick] = grid[pick][next];
    current = pick_max;
  }
  return path;
}

}  // namespace thermodec

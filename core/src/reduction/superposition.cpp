#include "thermodec/reduction/superposition.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace thermodec {

namespace {

// max |S| with NaN propagated (a NaN field fails every tolerance).
double max_abs(const Eigen::MatrixXd& s) {
  if (s.size() == 0) return 0.0;
  if (s.array().isNaN().any()) return std::numeric_limits<double>::quiet_NaN();
  return s.cwiseAbs().maxCoeff();
}

// The shape shared by every field (rows x cols), from the first curve with a sample.
bool field_shape(const std::vector<const SensitivityCurve*>& curve_of, Eigen::Index& rows, Eigen::Index& cols) {
  rows = cols = -1;
  for (const SensitivityCurve* c : curve_of) {
    if (!c) continue;
    if (c->dT_K.size() != c->ratios.size()) return false;
    for (const Eigen::MatrixXd& d : c->dT_K) {
      if (d.size() == 0) return false;
      if (rows < 0) rows = d.rows(), cols = d.cols();
      if (d.rows() != rows || d.cols() != cols) return false;
    }
  }
  return rows > 0;
}

}  // namespace

bool has_difference_fields(const std::vector<const SensitivityCurve*>& curve_of) {
  Eigen::Index rows, cols;
  return field_shape(curve_of, rows, cols);
}

Eigen::MatrixXd difference_field_at(const SensitivityCurve& c, double ratio) {
  const Eigen::MatrixXd zero = Eigen::MatrixXd::Zero(c.dT_K.front().rows(), c.dT_K.front().cols());
  if (!(ratio > 0.0)) return zero;
  double r0 = 0.0;
  const Eigen::MatrixXd* d0 = &zero;
  for (std::size_t i = 0; i < c.ratios.size(); ++i) {
    const double r1 = c.ratios[i];
    if (ratio <= r1 + 1e-12) {
      const double t = r1 > r0 ? std::clamp((ratio - r0) / (r1 - r0), 0.0, 1.0) : 1.0;
      return (1.0 - t) * *d0 + t * c.dT_K[i];
    }
    r0 = r1;
    d0 = &c.dT_K[i];
  }
  return *d0;
}

double superposed_max_abs_dT_K(const std::vector<const SensitivityCurve*>& curve_of,
                               const Eigen::VectorXd& ratio_per_node) {
  Eigen::Index rows, cols;
  if (!field_shape(curve_of, rows, cols)) return std::numeric_limits<double>::quiet_NaN();
  Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(rows, cols);
  for (std::size_t k = 0; k < curve_of.size(); ++k)
    if (curve_of[k] && k < static_cast<std::size_t>(ratio_per_node.size()) && ratio_per_node[k] > 0.0)
      sum += difference_field_at(*curve_of[k], ratio_per_node[k]);
  return max_abs(sum);
}

Eigen::VectorXd superposed_allocation(const std::vector<const SensitivityCurve*>& curve_of, int num_nodes,
                                      double target_K) {
  Eigen::Index rows, cols;
  Eigen::VectorXd ratios = Eigen::VectorXd::Zero(num_nodes);
  if (!field_shape(curve_of, rows, cols)) return ratios;
  std::vector<int> at(num_nodes, -1);  // index of the node's current sample, -1 = unreduced
  Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(rows, cols);
  double current = 0.0;
  // Faces a node removes by moving to sample i from sample i-1 (from its full count, estimated
  // from the first sample's ratio, for i = 0); by the ratio step if the trial did not say.
  auto faces_removed = [&](const SensitivityCurve& c, int i) {
    if (c.faces_after[i] < 0 || (i > 0 && c.faces_after[i - 1] < 0))
      return 100.0 * (c.ratios[i] - (i > 0 ? c.ratios[i - 1] : 0.0));
    const double before = i > 0 ? c.faces_after[i - 1] : c.faces_after[0] / std::max(1e-9, 1.0 - c.ratios[0]);
    return std::max(1.0, before - c.faces_after[i]);
  };
  while (true) {
    int pick = -1;
    double pick_score = -1.0, pick_max = 0.0;
    for (int k = 0; k < num_nodes && k < static_cast<int>(curve_of.size()); ++k) {
      const SensitivityCurve* c = curve_of[k];
      if (!c || at[k] + 1 >= static_cast<int>(c->ratios.size())) continue;
      const int next = at[k] + 1;
      Eigen::MatrixXd moved = sum + c->dT_K[next];
      if (at[k] >= 0) moved -= c->dT_K[at[k]];
      const double m = max_abs(moved);
      if (!(m <= target_K)) continue;  // NaN or over the target
      // Faces per kelvin of increase; a step that does not raise the prediction is worth its
      // faces times a large factor, so such steps go first, biggest first.
      const double increase = std::max(m - current, 1e-9 * target_K);
      const double score = faces_removed(*c, next) / increase;
      if (score > pick_score) pick_score = score, pick = k, pick_max = m;
    }
    if (pick < 0) break;
    const SensitivityCurve& c = *curve_of[pick];
    if (at[pick] >= 0) sum -= c.dT_K[at[pick]];
    sum += c.dT_K[++at[pick]];
    current = pick_max;
    ratios[pick] = c.ratios[at[pick]];
  }
  return ratios;
}

}  // namespace thermodec

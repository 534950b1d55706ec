#include "thermodec/reduction/prediction.h"

#include <algorithm>

namespace thermodec {

double feasible_ratio(const SensitivityCurve& curve, double budget_K) {
  double best = 0.0;
  for (size_t i = 0; i < curve.ratios.size(); ++i) {
    if (!(curve.max_abs_dT_K[i] <= budget_K)) break;  // NaN counts as a violation
    best = curve.ratios[i];
  }
  return best;
}

double predicted_difference_K(const SensitivityCurve& curve, double ratio) {
  double r0 = 0.0, d0 = 0.0, running = 0.0;
  for (size_t i = 0; i < curve.ratios.size(); ++i) {
    running = std::max(running, curve.max_abs_dT_K[i]);
    const double r1 = curve.ratios[i];
    if (ratio <= r1) {
      const double t = (r1 > r0) ? (ratio - r0) / (r1 - r0) : 1.0;
      return d0 + std::clamp(t, 0.0, 1.0) * (running - d0);
    }
    r0 = r1;
    d0 = running;
  }
  return running;  // beyond the sweep: at least the last measured value
}

double next_ratio(const SensitivityCurve& curve, double ratio) {
  for (double r : curve.ratios)
    if (r > ratio + 1e-12) return r;
  return ratio;
}

double previous_ratio(const SensitivityCurve& curve, double ratio) {
  double prev = 0.0;
  for (double r : curve.ratios) {
    if (r >= ratio - 1e-12) break;
    prev = r;
  }
  return prev;
}

}  // namespace thermodec

#pragma once
//! Prediction (paper §V.B): from a node's sensitivity curve, the largest reduction ratio
//! whose measured difference stays within a tolerance.
#include "thermodec/reduction/sensitivity.h"

namespace thermodec {

//! Largest sampled ratio r such that every sample with ratio <= r has max |dT| <= budget_K
//! (the curve's running maximum is used, so a noisy dip past a violation is never trusted).
//! Returns 0 when even the first sample exceeds the budget.
double feasible_ratio(const SensitivityCurve& curve, double budget_K);

//! The curve's running-maximum difference at `ratio` (linear between samples, 0 at ratio 0):
//! the predicted contribution of this node alone [K].
double predicted_difference_K(const SensitivityCurve& curve, double ratio);

//! The next sampled ratio above `ratio` on the curve, or `ratio` if none.
double next_ratio(const SensitivityCurve& curve, double ratio);
//! The sampled ratio below `ratio` on the curve, or 0 if none.
double previous_ratio(const SensitivityCurve& curve, double ratio);

}  // namespace thermodec

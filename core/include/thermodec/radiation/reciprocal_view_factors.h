#pragma once
//! Side-to-side view factors with reciprocity enforced, for the solar-band reflections.
#include "thermodec/radiation/face_view_factors.h"

namespace thermodec {

//! The view factors of `vf` with every pair of sides that see each other estimated from both
//! ends: A_s F_st and A_t F_ts are two independent Monte Carlo estimates of the same exchange
//! area [m^2] (reciprocity), so both entries are replaced by their mean weighted by ray density
//! (rays per m^2 of the emitting side, N_s / A_s), the inverse of each estimate's variance
//! A_s^2 F (1 - F) / N_s up to the common factor. The weights depend on the ray counts and
//! areas only, not on the estimates, so the combination stays unbiased. Each row's escaping
//! share takes what the row's entries gave up or gained (closure, rows sum to 1 as before; a row
//! whose entries would exceed 1 is scaled back to 1). Sides without area or rays keep their
//! own row, F(s, s) (a side seeing itself) is kept. Cost: two passes over the non-zeros, F_ts read
//! from a cursor per row t (one binary search per row and block of rows); memory: the result
//! (~ the size of F), no transpose.
//! Variance: where both ends draw equal ray densities, each exchange area's variance halves; where
//! one end is sampled k times more densely, it falls ~(k + 1)-fold for the sparse end's rows.
//! \return the same sides, ray counts and diagnostics with F and to_space replaced.
FaceViewFactors reciprocal_view_factors(const FaceViewFactors& vf);

}  // namespace thermodec

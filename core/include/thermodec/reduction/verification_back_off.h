#pragma once
//! Backing a rejected candidate off towards the unreduced model: when every search attempt's
//! candidate is rejected by the statistical verification, a less deep decimation of the least
//! rejected one (its per-node ratios scaled by s in (0, 1)) may still pass, where the unreduced
//! model (s = 0) would throw every reduction away.
#include <functional>

namespace thermodec {

//! Bisection of the scale s in (0, 1) between the unreduced model (s = 0, taken as accepted)
//! and the rejected candidate (s = 1): at most `steps` calls of accepts(s), the first at 1/2,
//! each next one half the last step up (accepted) or down (rejected). Returns the largest scale
//! accepted, 0 when none was (or steps <= 0). accepts is called with strictly increasing scales
//! after an acceptance and decreasing ones after a rejection; it is never called twice with
//! the same scale.
double back_off_scale(int steps, const std::function<bool(double scale)>& accepts);

}  // namespace thermodec

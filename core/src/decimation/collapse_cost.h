#pragma once
// Private to core/src/decimation: the cost of a candidate collapse, the one place where
// collapses are ranked (as PMP's priority() or libigl's cost_and_placement). Single and section
// collapses describe what they do to the faces around them (StarChange) after their validity
// checks passed; collapse_cost() turns that into the heap priority. Another criterion is
// another branch of collapse_cost(), nothing else.
#include "collapse_types.h"

namespace thermodec::collapse {

//! Priority of a collapse in vcg's heap (lower runs first), dimensionless, by
//! c.opt.collapse_cost. Precondition: the collapse passed its validity checks.
double collapse_cost(const Context& c, const StarChange& change);

//! Mean over all directions d of the squared change of sum_f max(0, N_f . d) per node, with
//! N_f the face's area vector, divided by the node's input area squared, summed over the
//! nodes the collapse touches (dimensionless).
double projected_area_change(const Context& c, const StarChange& change);

}  // namespace thermodec::collapse

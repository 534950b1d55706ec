#pragma once
//! Independent whole simulations run side by side. A full simulation's parallel loops leave a
//! core idle between them (scene builds, per-step passes, the thermal solve): two of them at
//! once fill those gaps. Results do not depend on it: each job writes only its own output.
#include <functional>

namespace thermodec {

//! Runs job(0) ... job(count - 1), at most `lanes` at once, each job's own parallel loops on
//! every thread; a lane takes the next job when its last one is done. Memory grows with the
//! lanes (each holds one job's working set), so callers keep them few (2).
//! \throw whatever a job throws (the first one; the other lanes finish their current job).
void run_side_by_side(int count, int lanes, const std::function<void(int)>& job);

}  // namespace thermodec

#include "thermodec/common/side_by_side.h"

#include <algorithm>
#include <atomic>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

namespace thermodec {

void run_side_by_side(int count, int lanes, const std::function<void(int)>& job) {
  if (count <= 0) return;
  lanes = std::max(1, std::min(lanes, count));
  if (lanes == 1) {
    for (int i = 0; i < count; ++i) job(i);
    return;
  }
  std::atomic<int> next{0};
  std::atomic<bool> failed{false};
  tbb::parallel_for(
      tbb::blocked_range<int>(0, lanes, 1),
      [&](const tbb::blocked_range<int>&) {
        // note: isolated, so that a thread waiting in its job's parallel loops does not take up
        // the other lane (a whole second job nested on its stack, holding the first one up).
        tbb::this_task_arena::isolate([&] {
          for (int i = next++; i < count && !failed; i = next++) {
            try {
              job(i);
            } catch (...) {
              failed = true;  // the other lanes take no further job
              throw;
            }
          }
        });
      },
      tbb::simple_partitioner());
}

}  // namespace thermodec

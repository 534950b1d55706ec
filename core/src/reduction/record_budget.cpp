#include "thermodec/reduction/record_budget.h"

#include <algorithm>

#include "thermodec/common/physical_memory.h"

namespace thermodec {

std::size_t default_record_budget_bytes() {
  const std::size_t standard = std::size_t(17) << 28;  // 4.25 GiB
  const long long ram = physical_memory_bytes();
  return ram > 0 ? std::min(standard, static_cast<std::size_t>(ram / 4)) : standard;
}

RecordBudget split_record_budget(std::size_t total_bytes) {
  RecordBudget b;
  b.earth_geometry_bytes = total_bytes / 17 * 2;
  b.records_bytes = total_bytes - b.earth_geometry_bytes;
  b.ir_max_bytes = b.records_bytes / 4 * 3;
  return b;
}

}  // namespace thermodec

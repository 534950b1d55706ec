#include "thermodec/common/physical_memory.h"

#include <unistd.h>

namespace thermodec {

long long physical_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0) return 0;
  return static_cast<long long>(pages) * page;
}

}  // namespace thermodec

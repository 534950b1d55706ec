#include "thermodec/common/peak_memory.h"

#include <sys/resource.h>

namespace thermodec {

long long peak_resident_memory_bytes() {
  struct rusage u {};
  if (getrusage(RUSAGE_SELF, &u) != 0) return 0;
#ifdef __APPLE__
  return static_cast<long long>(u.ru_maxrss);  // bytes on macOS
#else
  return static_cast<long long>(u.ru_maxrss) * 1024;  // KiB on Linux
#endif
}

}  // namespace thermodec

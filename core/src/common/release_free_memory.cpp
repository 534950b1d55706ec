#include "thermodec/common/release_free_memory.h"

#include <cstdlib>  // (defines __GLIBC__ on glibc systems)

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace thermodec {

void release_free_memory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

}  // namespace thermodec

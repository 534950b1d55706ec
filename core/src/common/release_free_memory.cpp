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

void keep_freed_memory_for_reuse() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_MAX, 0);                // large blocks from the heap, reused after free
  mallopt(M_TRIM_THRESHOLD, 0x7fffffff);  // the heap's free top kept (2 GiB, the largest int)
#endif
}

}  // namespace thermodec

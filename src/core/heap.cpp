#include "core/heap.hpp"

#include <cstdlib>  // defines __GLIBC__ where it applies
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace poreshell {

void keep_large_blocks_mapped() {
#if defined(__GLIBC__)
  static const int set = mallopt(M_MMAP_THRESHOLD, 1 << 20);
  (void)set;
#endif
}

void release_free_memory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

}  // namespace poreshell

#include "util/heap_reuse.h"

#include <cstdlib>  // defines __GLIBC__ on glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace brdfshot {

bool KeepFreedHeapMemory() {
#if defined(__GLIBC__)
  // 32 MB is glibc's cap on the mmap threshold (half its 64 MB heap size on
  // 64-bit systems); larger blocks (a 12 MP frame, the lobe tables) stay
  // mmap'd and go back to the kernel when freed. Fixing the threshold also
  // turns off its growth rule, whose trim threshold follows it.
  constexpr int kMmapThreshold = 32 << 20;
  constexpr int kNeverTrim = 0x7fffffff;
  return mallopt(M_MMAP_THRESHOLD, kMmapThreshold) == 1 && mallopt(M_TRIM_THRESHOLD, kNeverTrim) == 1;
#else
  return false;
#endif
}

}  // namespace brdfshot

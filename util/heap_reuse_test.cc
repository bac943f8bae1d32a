#include "util/heap_reuse.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace brdfshot {
namespace {

#if defined(__GLIBC__) && (__GLIBC__ > 2 || __GLIBC_MINOR__ >= 33)
// ctest runs each test in a process of its own, so glibc's defaults hold at
// the start: a 16 MB block would be mmap'd and unmapped when freed, its next
// use faulting in every page again. With the heap kept it comes from the heap
// and, freed, stays there as free memory for the next block.
TEST(HeapReuse, AFreedBlockStaysInTheHeapForTheNext) {
  ASSERT_TRUE(KeepFreedHeapMemory());
  const size_t bytes = size_t(16) << 20;
  const struct mallinfo2 before = mallinfo2();
  char* volatile p = static_cast<char*>(std::malloc(bytes));
  ASSERT_NE(p, nullptr);
  std::memset(p, 1, bytes);
  const struct mallinfo2 held = mallinfo2();
  EXPECT_EQ(held.hblks, before.hblks) << "the block was mmap'd";
  std::free(p);
  const struct mallinfo2 after = mallinfo2();
  EXPECT_GE(after.fordblks, bytes) << "the freed block went back to the kernel";
  EXPECT_GE(after.arena, before.arena + bytes);
}
#else
TEST(HeapReuse, AFreedBlockStaysInTheHeapForTheNext) { GTEST_SKIP() << "not glibc ≥ 2.33: the setting does not apply"; }
#endif

}  // namespace
}  // namespace brdfshot

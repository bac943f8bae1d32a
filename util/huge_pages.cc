#include "util/huge_pages.h"

#include <cstdint>
#include <cstdlib>
#include <opencv2/core/types_c.h>  // CV_AUTO_STEP

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace brdfshot {

bool AdviseHugePages(void* data, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::size_t kHuge = std::size_t(2) << 20;
  if (data == nullptr || bytes < 2 * kHuge) return false;  // no whole huge page inside
  const std::uintptr_t page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  const std::uintptr_t begin = (reinterpret_cast<std::uintptr_t>(data) + page - 1) / page * page;
  const std::uintptr_t end = (reinterpret_cast<std::uintptr_t>(data) + bytes) / page * page;
  if (end <= begin) return false;
  return madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE) == 0;
#else
  (void)data;
  (void)bytes;
  return false;
#endif
}

namespace {

constexpr std::size_t kHugePage = std::size_t(2) << 20;
constexpr std::size_t kHugeFrom = 4 * (std::size_t(1) << 20);

class HugePageAllocator : public cv::MatAllocator {
 public:
  cv::UMatData* allocate(int dims, const int* sizes, int type, void* data0, std::size_t* step, cv::AccessFlag,
                         cv::UMatUsageFlags) const override {
    // The bytes of a dense array, innermost dimension last; a caller's own
    // steps (data0 given) are kept, as cv::Mat's contract asks.
    std::size_t total = CV_ELEM_SIZE(type);
    for (int i = dims - 1; i >= 0; --i) {
      if (step) {
        if (data0 && step[i] != CV_AUTO_STEP) {
          CV_Assert(total <= step[i]);
          total = step[i];
        } else {
          step[i] = total;
        }
      }
      total *= static_cast<std::size_t>(sizes[i]);
    }
    void* data = data0;
    if (!data) {
      if (total >= kHugeFrom) {
        data = std::aligned_alloc(kHugePage, (total + kHugePage - 1) / kHugePage * kHugePage);
        if (!data) CV_Error(cv::Error::StsNoMem, "out of memory");
        AdviseHugePages(data, total);
      } else {
        data = cv::fastMalloc(total);
      }
    }
    cv::UMatData* u = new cv::UMatData(this);
    u->data = u->origdata = static_cast<uchar*>(data);
    u->size = total;
    if (data0) u->flags |= cv::UMatData::USER_ALLOCATED;
    return u;
  }

  bool allocate(cv::UMatData* u, cv::AccessFlag, cv::UMatUsageFlags) const override { return u != nullptr; }

  void deallocate(cv::UMatData* u) const override {
    if (!u) return;
    CV_Assert(u->urefcount == 0 && u->refcount == 0);
    if (!(u->flags & cv::UMatData::USER_ALLOCATED)) {
      // Which of the two allocated it follows from the size, as in allocate.
      if (u->size >= kHugeFrom)
        std::free(u->origdata);
      else
        cv::fastFree(u->origdata);
      u->origdata = nullptr;
    }
    delete u;
  }
};

}  // namespace

cv::MatAllocator* HugePageMatAllocator() {
  static HugePageAllocator allocator;
  return &allocator;
}

}  // namespace brdfshot

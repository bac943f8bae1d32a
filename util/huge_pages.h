// Asks the kernel to back a large buffer with transparent huge pages.
//
// Why: the basis images of a 256² sphere are 180 MB written once. With 4 KB
// pages their first touch is ~46 000 page faults, and on a virtual machine a
// fault is expensive: zeroing 180 MB of fresh memory took 0.67 s on the CI VM,
// a third of rendering all 300 bases, against 0.015 s with 2 MB pages. The
// advice is a hint (Linux `madvise(MADV_HUGEPAGE)`, honoured when THP is in
// `madvise` or `always` mode); elsewhere, or when refused, nothing changes.
#pragma once

#include <cstddef>
#include <opencv2/core.hpp>

namespace brdfshot {

// Advises the whole pages inside [data, data + bytes). Returns whether the
// kernel accepted the advice (false for buffers under 4 MB, other systems, or
// a kernel built without THP); with THP set to `never` it is accepted and
// ignored.
bool AdviseHugePages(void* data, std::size_t bytes);

// An OpenCV allocator that gives images of 4 MB and more 2 MB-aligned memory
// advised onto huge pages (smaller ones as OpenCV's own allocator would).
// Why: a 12 MP bracket is a dozen 36 MB frames decoded, converted and merged
// into fresh buffers; on a virtual machine their 4 KB page faults are a fifth
// of `merge`'s time with OpenCV's own allocator. `brdfshot` installs it for the whole process
// (cv::Mat::setDefaultAllocator) before running a command; the returned object
// lives as long as the process.
cv::MatAllocator* HugePageMatAllocator();

// Makes `a` OpenCV's allocator for the object's lifetime, then restores the
// one before. The benchmarks time each method as its own program would run
// (ours on huge pages, OpenCV's merges on OpenCV's allocator), whatever the
// calling process installed.
class ScopedMatAllocator {
 public:
  explicit ScopedMatAllocator(cv::MatAllocator* a) : previous_(cv::Mat::getDefaultAllocator()) {
    cv::Mat::setDefaultAllocator(a);
  }
  ~ScopedMatAllocator() { cv::Mat::setDefaultAllocator(previous_); }
  ScopedMatAllocator(const ScopedMatAllocator&) = delete;
  ScopedMatAllocator& operator=(const ScopedMatAllocator&) = delete;

 private:
  cv::MatAllocator* previous_;
};

}  // namespace brdfshot

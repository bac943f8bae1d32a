#include "util/huge_pages.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <opencv2/imgproc.hpp>
#include <numeric>
#include <string>
#include <vector>

namespace brdfshot {
namespace {

// What the kernel says of transparent huge pages: "always", "madvise" or
// "never" (the bracketed word), or "" where there is no such file.
std::string ThpMode() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string line;
  if (!std::getline(in, line)) return "";
  const size_t a = line.find('['), b = line.find(']');
  return a == std::string::npos || b == std::string::npos ? "" : line.substr(a + 1, b - a - 1);
}

TEST(HugePages, NothingIsAdvisedForBuffersWithoutAWholeHugePage) {
  std::vector<float> small(1000);
  EXPECT_FALSE(AdviseHugePages(small.data(), sizeof(float) * small.size()));
  EXPECT_FALSE(AdviseHugePages(nullptr, size_t(64) << 20));
}

TEST(HugePages, AdviceKeepsTheContentsAndIsTakenWhereTheKernelOffersIt) {
  // Written before the advice and read after: advice that dropped pages (as
  // MADV_DONTNEED would) reads back zeros.
  std::vector<int> v(size_t(8) << 20);  // 32 MB
  std::iota(v.begin(), v.end(), 1);
  const bool taken = AdviseHugePages(v.data(), sizeof(int) * v.size());
  for (size_t i = 0; i < v.size(); i += 4099) ASSERT_EQ(v[i], static_cast<int>(i + 1)) << i;
  EXPECT_EQ(v.back(), static_cast<int>(v.size()));
  const std::string mode = ThpMode();
  if (mode == "always" || mode == "madvise") {
    EXPECT_TRUE(taken) << "THP mode " << mode;
  }
}

// Images made through the allocator hold what the same operations give with
// OpenCV's own; large ones start on a 2 MB boundary (where huge pages can back
// them), small ones need not; an image over caller-owned memory is left to
// its owner.
TEST(HugePages, TheMatAllocatorGivesLargeImagesHugePageAlignedMemoryAndTheSameResults) {
  cv::Mat noise(1500, 1000, CV_32FC3);  // 18 MB
  cv::randu(noise, 0, 1);
  cv::Mat expected;
  cv::GaussianBlur(noise, expected, cv::Size(7, 7), 2);

  cv::MatAllocator* const opencv_own = cv::Mat::getDefaultAllocator();
  cv::Mat::setDefaultAllocator(HugePageMatAllocator());
  cv::Mat blurred, small(10, 10, CV_8UC3, cv::Scalar::all(7));
  cv::GaussianBlur(noise, blurred, cv::Size(7, 7), 2);
  std::vector<uint8_t> owned(size_t(6) << 20, 5);
  cv::Mat over_owned(static_cast<int>(owned.size() / 1024), 1024, CV_8U, owned.data());
  const cv::Mat owned_copy = over_owned.clone();
  cv::Mat::setDefaultAllocator(opencv_own);  // for the other tests

  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(blurred.data) % (size_t(2) << 20), 0u);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(owned_copy.data) % (size_t(2) << 20), 0u);
  EXPECT_EQ(cv::norm(blurred, expected, cv::NORM_INF), 0);
  EXPECT_EQ(cv::countNonZero(small.reshape(1) != 7), 0);
  EXPECT_EQ(over_owned.data, owned.data());
  EXPECT_EQ(cv::countNonZero(owned_copy != 5), 0);
  // Images made before the switch back are freed by the allocator that made
  // them (each remembers its own): releasing them here must not crash.
  blurred.release(), small.release(), over_owned.release();
  EXPECT_EQ(owned[0], 5);
}

}  // namespace
}  // namespace brdfshot

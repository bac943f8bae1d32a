#include "util/huge_pages.h"

#include <gtest/gtest.h>

#include <fstream>
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

}  // namespace
}  // namespace brdfshot

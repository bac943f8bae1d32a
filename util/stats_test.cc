#include "util/stats.h"

#include <gtest/gtest.h>

namespace brdfshot {

TEST(Median, OddEvenAndEmpty) {
  EXPECT_EQ(Median({3, 1, 2}), 2);
  EXPECT_EQ(Median({4, 1, 3, 2}), 2.5);
  EXPECT_EQ(Median({-1}), -1);
  EXPECT_EQ(Median({}), 0);
}

}  // namespace brdfshot

#include "fit/basis_tables.h"

#include <gtest/gtest.h>

#include <memory>
#include <vector>

namespace brdfshot {
namespace {

float SecondEntry(const TablesRef& t) { return t(0, 1); }
const float* DataOf(const TablesRef& t) { return t.data(); }

TEST(BasisTables, OwnsWhatItTakes) {
  MatrixXfR m(3, 4);
  m << 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12;
  const MatrixXfR want = m;
  const BasisTables t(std::move(m));
  EXPECT_FALSE(t.mapped());
  ASSERT_EQ(t.rows(), 3);
  ASSERT_EQ(t.cols(), 4);
  EXPECT_TRUE(t == want);
  EXPECT_EQ(t(2, 3), 12.0f);
}

TEST(BasisTables, CopiesShareTheStorageAndOutliveTheOriginal) {
  BasisTables copy, assigned;
  {
    MatrixXfR m = MatrixXfR::Constant(1000, 6, 2.5f);
    m(999, 5) = -1.0f;
    const BasisTables original(std::move(m));
    copy = BasisTables(original);
    assigned = original;
    EXPECT_EQ(copy.data(), original.data()) << "a copy shares, it does not duplicate";
    EXPECT_EQ(assigned.data(), original.data());
  }
  // The original is gone; the copies keep the storage alive.
  EXPECT_EQ(copy(999, 5), -1.0f);
  EXPECT_EQ(assigned(0, 0), 2.5f);
  EXPECT_EQ(assigned.rows(), 1000);
  assigned = BasisTables();
  EXPECT_EQ(assigned.rows(), 0);
  EXPECT_EQ(copy(999, 5), -1.0f) << "re-seating one copy leaves the other";
}

TEST(BasisTables, ViewsStorageItIsGivenAndPassesAsARefWithoutACopy) {
  auto storage = std::make_shared<std::vector<float>>(std::vector<float>{0, 1, 2, 3, 4, 5, 6, 7});
  const BasisTables view(storage, storage->data() + 2, 3, 2);
  EXPECT_TRUE(view.mapped());
  EXPECT_EQ(view(0, 0), 2.0f);
  EXPECT_EQ(view(2, 1), 7.0f);
  EXPECT_EQ(SecondEntry(view), 3.0f);
  EXPECT_EQ(DataOf(view), storage->data() + 2) << "passed by TablesRef without a copy";
  MatrixXfR m = MatrixXfR::Zero(2, 2);
  EXPECT_EQ(DataOf(m), m.data()) << "a MatrixXfR passes by TablesRef without a copy";
}

}  // namespace
}  // namespace brdfshot

#include "fit/merl_grid.h"

#include <gtest/gtest.h>

#include <cmath>

namespace brdfshot {

// The table is CosineWeight entry by entry, on MERL's grid and on a small one
// of odd sizes (so that no axis's index can stand in for another's).
TEST(MerlGrid, CosineWeightTableIsEachEntrysCosineWeight) {
  for (const MerlGrid grid : {MerlGrid{}, MerlGrid{7, 5, 11}}) {
    const std::vector<float> table = grid.CosineWeightTable();
    ASSERT_EQ(table.size(), grid.size());
    size_t measurable = 0, differ = 0;
    for (size_t idx = 0; idx < grid.size(); ++idx) {
      differ += table[idx] != static_cast<float>(grid.CosineWeight(idx));
      measurable += grid.Measurable(idx);
      EXPECT_EQ(table[idx] > 0, grid.Measurable(idx)) << "entry " << idx;
    }
    EXPECT_EQ(differ, 0u) << "of " << grid.size() << " entries";
    EXPECT_GT(measurable, grid.size() / 4);
    EXPECT_LT(measurable, grid.size());
  }
}

// Closed forms: with the half vector at the pole, ω_o mirrors ω_i about it and
// cos θ_i cos θ_o = cos² θ_d; with ω_i = ω_o (θ_d = 0), cos² θ_h.
TEST(MerlGrid, CosineWeightTableMatchesItsClosedFormsOnTheAxes) {
  const MerlGrid grid;
  const std::vector<float> table = grid.CosineWeightTable();
  for (int j = 0; j < grid.n_td; ++j)
    for (int k = 0; k < grid.n_pd; k += 17) {
      const double c = std::cos(grid.LatticePoint(0, j, k).theta_d);
      EXPECT_NEAR(table[grid.Index(0, j, k)], c * c, 1e-6) << "theta_d bin " << j;
    }
  for (int i = 0; i < grid.n_th; ++i) {
    const double c = std::cos(grid.LatticePoint(i, 0, 0).theta_h);
    EXPECT_NEAR(table[grid.Index(i, 0, 0)], c * c, 1e-6) << "theta_h bin " << i;
  }
}

}  // namespace brdfshot

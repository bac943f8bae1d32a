#include "fit/database.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "util/check.h"
#include "util/data_paths.h"

namespace brdfshot {

TEST(Database, GramMatchesADirectDoubleProduct) {
  MatrixXfR B(20000, 7);
  B.setRandom();
  B.col(3) *= 1000.0f;  // columns of very different scale, as metal vs fabric
  std::vector<float> w(B.rows());
  for (size_t i = 0; i < w.size(); ++i) w[i] = 0.5f + (i % 7) * 0.1f;
  const Eigen::MatrixXd Bd = B.cast<double>();
  const Eigen::MatrixXd want = Bd.transpose() * Bd;
  EXPECT_LT((GramMatrix(B) - want).norm(), 1e-6 * want.norm());
  Eigen::VectorXd wd(w.size());
  for (size_t i = 0; i < w.size(); ++i) wd[i] = w[i];
  const Eigen::MatrixXd want_w = Bd.transpose() * wd.array().square().matrix().asDiagonal() * Bd;
  EXPECT_LT((GramMatrix(B, &w) - want_w).norm(), 1e-6 * want_w.norm());
}

TEST(Database, StandinSubsetIsLabelledAndShaped) {
  const std::string tsv = DataPath("standin/materials.tsv");
  if (tsv.empty() || !std::filesystem::exists(tsv)) GTEST_SKIP() << "no stand-in";
  DatabaseOptions opt;
  opt.kind = "standin";
  opt.grid = MerlGrid{10, 10, 20};
  opt.only = {"metal-01", "diffuse-02"};
  const BasisDatabase db = LoadDatabase(opt);
  EXPECT_EQ(db.label, "stand-in (analytic)");
  EXPECT_EQ(db.num_bases(), 6);
  EXPECT_EQ(db.B.rows(), 2000);
  EXPECT_EQ(db.BasisName(4), "diffuse-02/G");
  EXPECT_GE(db.B.minCoeff(), 0.0f) << "unmeasured entries must be 0 in B";
  opt.only = {"no-such-material"};
  EXPECT_THROW(LoadDatabase(opt), Error);
}

TEST(Database, MissingDataSaysWhereToGetIt) {
  DatabaseOptions opt;
  opt.data_root = "/nonexistent-brdfshot-data";
  opt.kind = "merl";
  try {
    LoadDatabase(opt);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("BRDFSHOT_DATA"), std::string::npos) << e.what();
  }
}

TEST(Database, WithoutADataFolderAutoFindsTheRepositorysNeuralFits) {
  DatabaseOptions opt;
  opt.data_root = "/nonexistent-brdfshot-data";
  std::string folder;
  EXPECT_EQ(ResolveDatabaseKind(opt, &folder), "nbrdf");
  EXPECT_EQ(std::filesystem::path(folder),
            std::filesystem::weakly_canonical(std::filesystem::path(BRDFSHOT_SOURCE_DIR) / "data" / "merl-nbrdf"));
  EXPECT_EQ(ReadLines(folder + "/materials.txt").size(), 100u);
}

TEST(Database, SelectMaterialsKeepsExcludesAndSpreads) {
  const std::vector<std::string> names = {"a", "b", "c", "d", "e", "f"};
  DatabaseOptions o;
  o.exclude = {"c"};
  EXPECT_EQ(SelectMaterials(names, o), (std::vector<int>{0, 1, 3, 4, 5}));
  o.only = {"e", "c", "a"};
  EXPECT_EQ(SelectMaterials(names, o), (std::vector<int>{4, 0}));  // the order asked, minus the excluded
  o.only.clear();
  o.max_materials = 2;  // spread over what the exclusion left: items 0 and 2 of {0,1,3,4,5}
  EXPECT_EQ(SelectMaterials(names, o), (std::vector<int>{0, 3}));
  o.exclude = {"zz"};
  try {
    SelectMaterials(names, o);
    FAIL() << "no error for an unknown excluded material";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'zz'"), std::string::npos) << e.what();
  }
}

}  // namespace brdfshot

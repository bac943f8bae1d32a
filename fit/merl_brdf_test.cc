#include "fit/merl_brdf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <cstring>
#include <unistd.h>

#include "fit/standin.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/data_paths.h"

namespace brdfshot {
namespace fs = std::filesystem;

namespace {
std::vector<StandinMaterial> Table() {
  const std::string path = DataPath("standin/materials.tsv");
  if (path.empty() || !fs::exists(path)) return {};
  return ReadStandinTable(path);
}
const StandinMaterial* Find(const std::vector<StandinMaterial>& t, const std::string& family) {
  for (const auto& m : t)
    if (m.family == family) return &m;
  return nullptr;
}
std::string Tmp(const std::string& name) {
  return (fs::temp_directory_path() / ("brdfshot_" + std::to_string(::getpid()) + "_" + name)).string();
}
}  // namespace

TEST(HalfDiff, RoundTripThroughDirections) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  for (int n = 0; n < 500; ++n) {
    HalfDiff hd{u(rng) * kPi / 2, u(rng) * kPi / 2, u(rng) * 2 * kPi};
    Vec3 wi, wo;
    FromHalfDiff(hd, &wi, &wo);
    const HalfDiff back = ToHalfDiff(wi, wo);
    EXPECT_NEAR(back.theta_h, hd.theta_h, 1e-7);
    EXPECT_NEAR(back.theta_d, hd.theta_d, 1e-7);
    if (hd.theta_d > 1e-3 && hd.theta_h > 1e-3) {
      EXPECT_NEAR(std::remainder(back.phi_d - hd.phi_d, 2 * kPi), 0, 1e-6);
    }
  }
}

TEST(MerlBrdf, RoundTripIsBitExact) {
  const auto table = Table();
  if (table.empty()) GTEST_SKIP() << "no stand-in table";
  const MerlBrdf m = table[0].ToMerl(MerlGrid{16, 16, 32});
  const std::string a = Tmp("a.binary"), b = Tmp("b.binary");
  m.Write(a);
  MerlBrdf::Read(a).Write(b);
  EXPECT_EQ(ReadFileBytes(a), ReadFileBytes(b));
  EXPECT_EQ(ReadFileBytes(a).size(), 12 + 3 * 16 * 16 * 32 * 8u);
  fs::remove(a);
  fs::remove(b);
}

TEST(MerlBrdf, LookupMatchesTheAnalyticBrdfAtLatticePoints) {
  const auto table = Table();
  if (table.empty()) GTEST_SKIP() << "no stand-in table";
  const MerlGrid grid = MerlGrid::Full();
  for (const char* family : {"diffuse", "metal", "paint"}) {
    const StandinMaterial* mat = Find(table, family);
    ASSERT_NE(mat, nullptr);
    const MerlBrdf m = mat->ToMerl(grid);
    std::mt19937 rng(11);
    int checked = 0;
    while (checked < 300) {
      const int i = rng() % grid.n_th, j = rng() % grid.n_td, k = rng() % grid.n_pd;
      Vec3 wi, wo;
      FromHalfDiff(grid.LatticePoint(i, j, k), &wi, &wo);
      if (wi.z < 1e-3 || wo.z < 1e-3) continue;
      const Rgb want = mat->Eval(wi, wo), got = m.Eval(wi, wo);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(got[c], want[c], 1e-6 * want[c] + 1e-12) << family << " " << i << "," << j << "," << k;
      ++checked;
    }
  }
}

TEST(MerlBrdf, LookupBetweenBinsIsWithinStatedTolerance) {
  // Between lattice points the table is trilinear in (√θ_h, θ_d, φ_d). For smooth
  // (diffuse / plastic) materials away from grazing angles the error against the
  // closed form is below 2 %; stated in docs/formats.md "MERL tables".
  const auto table = Table();
  if (table.empty()) GTEST_SKIP() << "no stand-in table";
  for (const char* family : {"diffuse", "plastic"}) {
    const StandinMaterial* mat = Find(table, family);
    const MerlBrdf m = mat->ToMerl(MerlGrid::Full());
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0, 1);
    double worst = 0;
    for (int n = 0; n < 2000; ++n) {
      const Vec3 wi = Normalize(Vec3(u(rng) - 0.5, u(rng) - 0.5, 0.3 + u(rng)));
      const Vec3 wo = Normalize(Vec3(u(rng) - 0.5, u(rng) - 0.5, 0.3 + u(rng)));
      const Rgb want = mat->Eval(wi, wo), got = m.Eval(wi, wo);
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(got[c] - want[c]) / want[c]);
    }
    EXPECT_LT(worst, 0.02) << family;
  }
}

TEST(MerlBrdf, LookupIsReciprocal) {
  const auto table = Table();
  if (table.empty()) GTEST_SKIP() << "no stand-in table";
  const MerlBrdf m = Find(table, "paint")->ToMerl(MerlGrid{45, 45, 90});
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int n = 0; n < 1000; ++n) {
    const Vec3 a = Normalize(Vec3(u(rng), u(rng), 1.2 + u(rng)));
    const Vec3 b = Normalize(Vec3(u(rng), u(rng), 1.2 + u(rng)));
    const Rgb ab = m.Eval(a, b), ba = m.Eval(b, a);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(ab[c], ba[c], 1e-9 * (1 + ab[c]));
  }
}

TEST(MerlBrdf, BelowHorizonIsZeroAndUnmeasuredIsMarked) {
  const auto table = Table();
  if (table.empty()) GTEST_SKIP() << "no stand-in table";
  const MerlBrdf m = table[0].ToMerl(MerlGrid{30, 30, 60});
  const Rgb r = m.Eval(Normalize(Vec3(1, 0, -0.1)), Vec3(0, 0, 1));
  EXPECT_EQ(r.r + r.g + r.b, 0);
  // Entries whose directions are below the horizon are stored negative.
  EXPECT_GT(m.UnmeasuredFraction(), 0.05);
  EXPECT_LT(m.UnmeasuredFraction(), 0.6);
}

// A new table is unmeasured everywhere, on MERL's grid (35 MB, on huge pages
// where the kernel grants them) as on a small one.
TEST(MerlBrdf, ANewTableIsUnmeasuredAtEveryEntry) {
  for (const MerlGrid grid : {MerlGrid{}, MerlGrid{3, 4, 5}}) {
    const MerlBrdf m(grid);
    size_t other = 0;
    for (int c = 0; c < 3; ++c)
      for (size_t idx = 0; idx < grid.size(); ++idx) other += m.raw(c, idx) != -1.0;
    EXPECT_EQ(other, 0u) << grid.size() << " entries";
    EXPECT_EQ(m.UnmeasuredFraction(), 1.0);
  }
}

class MerlBadFileTest : public ::testing::Test {
 protected:
  void ExpectNamedError(const std::string& bytes, const std::string& fragment) {
    const std::string path = Tmp("bad.binary");
    { std::ofstream(path, std::ios::binary) << bytes; }
    try {
      MerlBrdf::Read(path);
      ADD_FAILURE() << "expected an error for " << fragment;
    } catch (const Error& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(path), std::string::npos) << msg;
      EXPECT_NE(msg.find(fragment), std::string::npos) << msg;
    }
    fs::remove(path);
  }
  static std::string File(int32_t a, int32_t b, int32_t c, size_t doubles, double fill) {
    std::string s(12 + doubles * 8, '\0');
    const int32_t d[3] = {a, b, c};
    std::memcpy(&s[0], d, 12);
    for (size_t i = 0; i < doubles; ++i) std::memcpy(&s[12 + 8 * i], &fill, 8);
    return s;
  }
};

TEST_F(MerlBadFileTest, TruncatedFile) { ExpectNamedError(File(4, 4, 8, 3 * 128 - 5, 1.0), "truncated"); }
TEST_F(MerlBadFileTest, WrongHeader) { ExpectNamedError(File(-90, 90, 180, 10, 1.0), "header"); }
TEST_F(MerlBadFileTest, ShortHeader) { ExpectNamedError("abc", "too short"); }
TEST_F(MerlBadFileTest, NaNFilled) {
  ExpectNamedError(File(4, 4, 8, 3 * 128, std::numeric_limits<double>::quiet_NaN()), "NaN");
}
TEST_F(MerlBadFileTest, FolderInsteadOfFile) {
  try {
    MerlBrdf::Read(fs::temp_directory_path().string());
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("folder"), std::string::npos);
  }
}

TEST(MerlRealData, KnownFactsOfTheMerlDatabase) {
  const std::string dir = DataPath("merl");
  std::vector<std::string> files;
  std::error_code ec;
  if (!dir.empty() && fs::is_directory(dir, ec))
    for (auto& e : fs::directory_iterator(dir))
      if (e.path().extension() == ".binary") files.push_back(e.path().string());
  if (files.empty()) GTEST_SKIP() << "no real MERL files in <data>/merl";
  EXPECT_EQ(3 * files.size(), 300u);
  const MerlBrdf m = MerlBrdf::Read(files.front());
  EXPECT_TRUE(m.grid() == MerlGrid::Full());
  // About a third of MERL's entries lie below the horizon and are negative.
  EXPECT_GT(m.UnmeasuredFraction(), 0.2);
  EXPECT_LT(m.UnmeasuredFraction(), 0.6);
}

}  // namespace brdfshot

namespace brdfshot {

// Found by fuzz_merl: a header claiming a 4000³ table in a 12-byte file must be
// refused by its size before 1.5 TB is allocated (bad_alloc is not FileError).
TEST(MerlBrdf, HugeHeaderInATinyFileIsRefusedBeforeAllocating) {
  const std::string path = (std::filesystem::temp_directory_path() / "brdfshot_huge_header.binary").string();
  {
    std::ofstream out(path, std::ios::binary);
    const int32_t dims[3] = {4000, 4000, 4000};
    out.write(reinterpret_cast<const char*>(dims), sizeof dims);
  }
  try {
    MerlBrdf::Read(path);
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("does not match header"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

}  // namespace brdfshot

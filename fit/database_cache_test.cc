#include "fit/database_cache.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "fit/test_databases.h"
#include "util/check.h"
#include "util/data_paths.h"

namespace brdfshot {
namespace fs = std::filesystem;

namespace {

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("brdfshot-cache-test-" + std::to_string(::getpid()) + "-" +
                                        std::to_string(reinterpret_cast<uintptr_t>(this)));
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

void FlipByte(const fs::path& file, uint64_t offset) {
  std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
  f.seekg(static_cast<std::streamoff>(offset));
  char c = 0;
  f.read(&c, 1);
  c ^= 0x10;
  f.seekp(static_cast<std::streamoff>(offset));
  f.write(&c, 1);
}

std::string ErrorOf(const std::function<void()>& call) {
  try {
    call();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(DatabaseCache, RoundTripsExactlyAndSelectsColumns) {
  const BasisDatabase db = LoadDatabase(DemoStandins(MerlGrid{6, 6, 12}));
  ASSERT_EQ(db.num_materials(), 16);
  const Eigen::MatrixXd gram = GramMatrix(db.B);
  const std::vector<float> w = db.grid.CosineWeightTable();
  const Eigen::MatrixXd gram_cos = GramMatrix(db.B, &w);
  TempDir dir;
  const CachedDatabaseId id{"standin", db.grid, "0123456789abcdef"};
  const std::string path = (dir.path / id.FileName()).string();
  WriteDatabaseCache(path, id, db, gram, gram_cos);

  std::vector<int> all(16);
  for (int i = 0; i < 16; ++i) all[i] = i;
  const BasisDatabase back = ReadDatabaseCache(path, id, all);
  EXPECT_EQ(back.materials, db.materials);
  EXPECT_EQ(back.families, db.families);
  EXPECT_EQ(back.label, db.label);
  ASSERT_EQ(back.B.rows(), db.B.rows());
  EXPECT_EQ(std::memcmp(back.B.data(), db.B.data(), sizeof(float) * db.B.size()), 0) << "not bit-exact";
  // Every material in the file's order: a view of the mapped file, B at a
  // page boundary of it (the padded header); any other selection a copy.
  EXPECT_TRUE(back.B.mapped());
  EXPECT_EQ(reinterpret_cast<uintptr_t>(back.B.data()) % 4096, 0u);

  std::vector<int> reversed(all.rbegin(), all.rend());  // every material, another order
  const BasisDatabase back_reversed = ReadDatabaseCache(path, id, reversed);
  EXPECT_EQ(back_reversed.materials.front(), db.materials.back());
  EXPECT_TRUE(back_reversed.B.col(0) == db.B.col(45));
  EXPECT_FALSE(back_reversed.B.mapped());

  const BasisDatabase some = ReadDatabaseCache(path, id, {5, 2});
  ASSERT_EQ(some.B.cols(), 6);
  EXPECT_EQ(some.materials, (std::vector<std::string>{db.materials[5], db.materials[2]}));
  for (int c = 0; c < 3; ++c) {
    EXPECT_TRUE(some.B.col(c) == db.B.col(15 + c));
    EXPECT_TRUE(some.B.col(3 + c) == db.B.col(6 + c));
  }
  const DatabaseGrams g = ReadDatabaseCacheGrams(path, id, {5, 2});
  EXPECT_TRUE(g.gram == gram(std::vector<int>{15, 16, 17, 6, 7, 8}, std::vector<int>{15, 16, 17, 6, 7, 8}));
  EXPECT_TRUE(g.gram_cos(0, 0) == gram_cos(15, 15));
}

TEST(DatabaseCache, DamagedTruncatedOrForeignFilesAreRefusedNamingTheFile) {
  DatabaseOptions opt = DemoStandins(MerlGrid{6, 6, 12});
  opt.only = {"demo-gold", "demo-felt"};
  const BasisDatabase db = LoadDatabase(opt);
  const Eigen::MatrixXd gram = GramMatrix(db.B);
  TempDir dir;
  const CachedDatabaseId id{"standin", db.grid, "00000000000000aa"};
  const std::string path = (dir.path / id.FileName()).string();
  WriteDatabaseCache(path, id, db, gram, gram);
  const uint64_t size = fs::file_size(path);

  const fs::path damaged = dir.path / "damaged.bsdb";
  fs::copy_file(path, damaged);
  FlipByte(damaged, size - 8 * 10 - 1000);  // inside B's last block
  std::string e = ErrorOf([&] { ReadDatabaseCache(damaged.string(), id, {0, 1}); });
  EXPECT_NE(e.find(damaged.string()), std::string::npos) << e;
  EXPECT_NE(e.find("checksum"), std::string::npos) << e;
  e = ErrorOf([&] { ReadDatabaseCache(damaged.string(), id, {1}); });  // a copy of some columns
  EXPECT_NE(e.find("checksum"), std::string::npos) << e;

  const fs::path shortfile = dir.path / "short.bsdb";
  fs::copy_file(path, shortfile);
  fs::resize_file(shortfile, size / 2);
  e = ErrorOf([&] { ReadDatabaseCache(shortfile.string(), id, {0, 1}); });
  EXPECT_NE(e.find("truncated"), std::string::npos) << e;
  e = ErrorOf([&] { ReadDatabaseCacheGrams(shortfile.string(), id, {0, 1}); });
  EXPECT_NE(e.find("truncated"), std::string::npos) << e;

  CachedDatabaseId other = id;
  other.fingerprint = "00000000000000bb";  // the source files changed
  e = ErrorOf([&] { ReadDatabaseCache(path, other, {0, 1}); });
  EXPECT_NE(e.find("another database or source version"), std::string::npos) << e;
}

TEST(DatabaseCache, LoadDatabaseRebuildsADamagedCacheWithAWarning) {
  TempDir dir;
  ::setenv("BRDFSHOT_CACHE", dir.path.c_str(), 1);
  DatabaseOptions opt = DemoStandins(MerlGrid{6, 6, 12});
  const BasisDatabase direct = LoadDatabase(opt);  // use_cache = false
  opt.use_cache = true;
  opt.exclude = {"demo-gold"};

  testing::internal::CaptureStderr();
  const BasisDatabase first = LoadDatabase(opt);
  const std::string built = testing::internal::GetCapturedStderr();
  EXPECT_NE(built.find("built the database cache"), std::string::npos) << built;
  std::vector<fs::path> files;
  for (const auto& f : fs::directory_iterator(dir.path)) files.push_back(f.path());
  ASSERT_EQ(files.size(), 1u) << "one cache file, no temporaries left";

  FlipByte(files[0], fs::file_size(files[0]) / 2);
  testing::internal::CaptureStderr();
  const BasisDatabase second = LoadDatabase(opt);
  const std::string warned = testing::internal::GetCapturedStderr();
  EXPECT_NE(warned.find("rebuilding"), std::string::npos) << warned;
  EXPECT_NE(warned.find(files[0].string()), std::string::npos) << warned;

  testing::internal::CaptureStderr();
  const BasisDatabase third = LoadDatabase(opt);  // the rebuilt cache is sound
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  ::unsetenv("BRDFSHOT_CACHE");

  // Every route gives the directly computed tables, demo-gold left out.
  std::vector<int> cols;
  for (int m = 0; m < direct.num_materials(); ++m)
    if (direct.materials[m] != "demo-gold")
      for (int c = 0; c < 3; ++c) cols.push_back(3 * m + c);
  const MatrixXfR want = direct.B(Eigen::all, cols);
  for (const BasisDatabase* got : {&first, &second, &third}) {
    ASSERT_EQ(got->B.cols(), want.cols());
    EXPECT_TRUE(got->B == want);
  }
}

TEST(DatabaseCache, ChecksumSeesEveryWord) {
  std::vector<uint64_t> words(1000, 7);
  const uint64_t h = Checksum64(words.data(), words.size() * 8);
  for (size_t i : {size_t{0}, size_t{1}, size_t{499}, size_t{998}, size_t{999}}) {
    std::vector<uint64_t> changed = words;
    changed[i] ^= 1;
    EXPECT_NE(Checksum64(changed.data(), changed.size() * 8), h) << "word " << i;
  }
  std::vector<uint64_t> swapped = words;
  swapped[3] = 9, swapped[4] = 7;
  std::vector<uint64_t> swapped2 = words;
  swapped2[3] = 7, swapped2[4] = 9;
  EXPECT_NE(Checksum64(swapped.data(), 8000), Checksum64(swapped2.data(), 8000));
  // Two words of one lane (32 words apart), swapped: each lane's chain is
  // ordered.
  std::vector<uint64_t> lane_a = words, lane_b = words;
  lane_a[5] = 9, lane_b[37] = 9;
  EXPECT_NE(Checksum64(lane_a.data(), 8000), Checksum64(lane_b.data(), 8000));
  EXPECT_NE(Checksum64(words.data(), 7999), h) << "length counts";
}

}  // namespace brdfshot

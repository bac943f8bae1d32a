#include "util/atomic_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "util/check.h"

namespace brdfshot {
namespace fs = std::filesystem;

class AtomicFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("brdfshot_atomic_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(AtomicFileTest, FailedWriterLeavesOldFileUntouchedAndNoTemp) {
  const std::string path = (dir_ / "out.txt").string();
  WriteFileAtomic(path, [](std::ostream& o) { o << "old"; });
  EXPECT_THROW(WriteFileAtomic(path,
                               [](std::ostream& o) {
                                 o << "partial";
                                 throw Error("boom");
                               }),
               Error);
  EXPECT_EQ(ReadFileBytes(path), "old");
  int files = 0;
  for (auto& e : fs::directory_iterator(dir_)) {
    (void)e;
    ++files;
  }
  EXPECT_EQ(files, 1) << "temporary file left behind";
}

TEST_F(AtomicFileTest, OutputThatIsAFolderIsANamedError) {
  try {
    WriteFileAtomic(dir_.string(), [](std::ostream& o) { o << "x"; });
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(dir_.string()), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("folder"), std::string::npos);
  }
}

TEST_F(AtomicFileTest, MissingOutputFolderIsANamedError) {
  const std::string path = (dir_ / "nope" / "x.bin").string();
  EXPECT_THROW(WriteFileAtomic(path, [](std::ostream& o) { o << "x"; }), Error);
  EXPECT_FALSE(fs::exists(path));
}

TEST_F(AtomicFileTest, ReadMissingFileNamesIt) {
  const std::string path = (dir_ / "missing.bin").string();
  try {
    ReadFileBytes(path);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("missing.bin"), std::string::npos);
  }
}

}  // namespace brdfshot

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

// A link replaces the old output whole, gives the linked file's bytes, leaves
// that file as it was and leaves no temporary; a link onto itself changes
// nothing; a missing file to link to is an error naming it.
TEST_F(AtomicFileTest, LinkReplacesTheOutputWithTheLinkedFilesBytes) {
  const std::string source = (dir_ / "shared.bin").string(), out = (dir_ / "out.bin").string();
  WriteFileAtomic(source, [](std::ostream& o) { o << "images"; });
  WriteFileAtomic(out, [](std::ostream& o) { o << "an older output"; });
  ASSERT_TRUE(LinkFileAtomic(source, out));
  EXPECT_EQ(ReadFileBytes(out), "images");
  EXPECT_EQ(ReadFileBytes(source), "images");
  EXPECT_TRUE(fs::equivalent(source, out));
  EXPECT_EQ(fs::hard_link_count(source), 2u);
  int files = 0;
  for (auto& e : fs::directory_iterator(dir_)) {
    (void)e;
    ++files;
  }
  EXPECT_EQ(files, 2) << "temporary link left behind";
  // Replacing one name later (as every writer here does) leaves the other.
  WriteFileAtomic(out, [](std::ostream& o) { o << "new"; });
  EXPECT_EQ(ReadFileBytes(source), "images");
  EXPECT_TRUE(LinkFileAtomic(source, source));
  EXPECT_EQ(ReadFileBytes(source), "images");
  try {
    LinkFileAtomic((dir_ / "absent.bin").string(), out);
    ADD_FAILURE() << "linking to a missing file must throw";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("absent.bin"), std::string::npos) << e.what();
  }
  EXPECT_EQ(ReadFileBytes(out), "new");
}

}  // namespace brdfshot

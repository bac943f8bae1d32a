#include "util/mapped_file.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "util/check.h"

namespace brdfshot {
namespace {

std::string TempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("brdfshot_mapped_" + name)).string();
}

TEST(MappedFile, HoldsTheFilesBytes) {
  const std::string path = TempPath("bytes");
  std::string bytes(70000, '\0');
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<char>((i * 131) % 251);
  std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  for (bool populate : {false, true}) {
    const MappedFile m(path, populate);
    ASSERT_EQ(m.size(), bytes.size());
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(m.data()), m.size()), bytes) << "populate " << populate;
  }
  std::filesystem::remove(path);
}

TEST(MappedFile, KeepsItsContentsWhenTheFileIsReplacedByRename) {
  const std::string path = TempPath("renamed"), next = TempPath("renamed.next");
  std::ofstream(path, std::ios::binary) << "first contents";
  const MappedFile m(path);
  std::ofstream(next, std::ios::binary) << "other contents, longer";
  std::filesystem::rename(next, path);
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(m.data()), m.size()), "first contents");
  EXPECT_EQ(MappedFile(path).size(), std::string("other contents, longer").size());
  std::filesystem::remove(path);
}

TEST(MappedFile, EmptyFileMapsToNothing) {
  const std::string path = TempPath("empty");
  std::ofstream(path, std::ios::binary).flush();
  const MappedFile m(path);
  EXPECT_EQ(m.size(), 0u);
  EXPECT_EQ(m.data(), nullptr);
  std::filesystem::remove(path);
}

TEST(MappedFile, MissingFileNamesIt) {
  const std::string path = TempPath("missing-file");
  std::filesystem::remove(path);
  try {
    const MappedFile m(path);
    FAIL() << "no error for a missing file";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace brdfshot

#include "util/data_paths.h"

#include <cstdlib>
#include <filesystem>

namespace brdfshot {
namespace fs = std::filesystem;

#ifndef BRDFSHOT_SOURCE_DIR_FALLBACK
#define BRDFSHOT_SOURCE_DIR_FALLBACK ""
#endif

namespace {
bool IsDir(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec);
}
}  // namespace

std::string DataRoot(const std::string& flag) {
  if (!flag.empty()) return flag;
  if (const char* env = std::getenv("BRDFSHOT_DATA"); env && *env) return env;
  for (const fs::path& candidate :
       {fs::path("../shared"), fs::path(BRDFSHOT_SOURCE_DIR_FALLBACK) / ".." / "shared"}) {
    if (IsDir(candidate)) return fs::weakly_canonical(candidate).string();
  }
  return "";
}

std::string DataPath(const std::string& relative, const std::string& root_flag) {
  const std::string root = DataRoot(root_flag);
  if (root.empty()) return "";
  return (fs::path(root) / relative).string();
}

std::string AssetPath(const std::string& relative) {
  for (const fs::path& base :
       {fs::path("samples/assets"), fs::path(BRDFSHOT_SOURCE_DIR_FALLBACK) / "samples" / "assets"}) {
    const fs::path p = base / relative;
    std::error_code ec;
    if (fs::exists(p, ec)) return p.string();
  }
  return "";
}

}  // namespace brdfshot

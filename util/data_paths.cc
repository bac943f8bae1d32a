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
  for (const fs::path& candidate : {fs::path("../shared"), fs::path(BRDFSHOT_SOURCE_DIR_FALLBACK) / ".." / "shared"}) {
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

std::string RepoDataPath(const std::string& relative) {
  for (const fs::path& base :
       {fs::path("data"), fs::path("../data"), fs::path(BRDFSHOT_SOURCE_DIR_FALLBACK) / "data"}) {
    const fs::path p = base / relative;
    std::error_code ec;
    if (fs::exists(p, ec)) return fs::weakly_canonical(p, ec).string();
  }
  return "";
}

std::string CacheDir() {
  if (const char* env = std::getenv("BRDFSHOT_CACHE"); env && *env) return std::string(env) == "off" ? "" : env;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return (fs::path(xdg) / "brdfshot").string();
  if (const char* home = std::getenv("HOME"); home && *home) return (fs::path(home) / ".cache" / "brdfshot").string();
  return "";
}

}  // namespace brdfshot

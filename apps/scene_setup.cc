#include "apps/scene_setup.h"

#include <algorithm>
#include <filesystem>

#include "apps/common_options.h"
#include "util/check.h"
#include "util/data_paths.h"

namespace brdfshot {

std::vector<std::string> ResolveProbes(const std::string& list, const std::string& data_root) {
  std::vector<std::string> probes = SplitList(list);
  if (!probes.empty()) return probes;
  const std::string dir = DataPath("envmaps", data_root);
  std::error_code ec;
  if (!dir.empty() && std::filesystem::is_directory(dir, ec))
    for (const auto& e : std::filesystem::directory_iterator(dir))
      if (e.path().extension() == ".exr") probes.push_back(e.path().string());
  std::sort(probes.begin(), probes.end());
  if (probes.empty())
    throw Error("no probes given and none in <data>/envmaps ('" + dir + "'): pass --probes a.exr,b.exr");
  return probes;
}

}  // namespace brdfshot

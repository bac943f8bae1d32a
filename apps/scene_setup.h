// Shared set-up of apps that render: which probes, which pixels.
#pragma once

#include <string>
#include <vector>

namespace brdfshot {

// Comma-separated probe paths, or every .exr in <data>/envmaps when empty.
std::vector<std::string> ResolveProbes(const std::string& list, const std::string& data_root);

}  // namespace brdfshot

// Where third-party data lives. Nothing of it is in the repository: users point
// BRDFSHOT_DATA (or a flag) at a folder laid out like the team's shared/ folder
// (merl/, merl-nbrdf/, standin/, envmaps/, real/), and ../shared next to the
// checkout is the fallback.
#pragma once

#include <string>

namespace brdfshot {

// The data root: `flag` if non-empty, else $BRDFSHOT_DATA, else the first existing
// of ./../shared, <source>/../shared. Returns "" when none exists.
std::string DataRoot(const std::string& flag = "");

// `relative` under the data root, or "" when there is no root.
std::string DataPath(const std::string& relative, const std::string& root_flag = "");

// The folder of the repository's own small assets (samples/assets), found beside
// the executable's source tree; "" when not found.
std::string AssetPath(const std::string& relative);

}  // namespace brdfshot

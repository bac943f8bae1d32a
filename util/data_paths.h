// Where data lives. The repository carries only what the demo needs (data/:
// MERL's materials as neural fits; samples/assets/: a small probe and demo
// stand-ins). Everything else is found through BRDFSHOT_DATA (or a flag), a
// folder laid out like the team's shared/ folder (merl/, merl-nbrdf/, standin/,
// envmaps/, real/), with ../shared next to the checkout as the fallback.
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

// `relative` under the repository's data/ folder (found in the working folder's
// parent chain up to the source tree the executable was built from); "" when
// not found.
std::string RepoDataPath(const std::string& relative);

// The folder for caches this machine rebuilds when they are missing or stale:
// $BRDFSHOT_CACHE, else $XDG_CACHE_HOME/brdfshot, else $HOME/.cache/brdfshot.
// "" when BRDFSHOT_CACHE is "off" or no home folder is known (no caching).
std::string CacheDir();

}  // namespace brdfshot

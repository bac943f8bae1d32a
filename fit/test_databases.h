// Test helpers shared by fit's tests (not part of the library).
#pragma once

#include <string>

#include "fit/database.h"

namespace brdfshot {

// The repository's 16 demo stand-ins on a small grid, computed afresh (no
// cache): a real database small enough for a unit test.
inline DatabaseOptions DemoStandins(MerlGrid grid = MerlGrid{10, 10, 20}) {
  DatabaseOptions o;
  o.kind = "standin";
  o.data_root = std::string(BRDFSHOT_SOURCE_DIR) + "/samples/assets";
  o.grid = grid;
  o.use_cache = false;
  return o;
}

}  // namespace brdfshot

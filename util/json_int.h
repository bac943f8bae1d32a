// Integer fields of the JSON the stages read. A corrupt file can hold 1e300,
// −5 or 2.5 where a count belongs, and converting such a number to int is
// undefined behaviour (fuzz_json found a sphere file whose width was 6e117).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "util/check.h"

namespace brdfshot {

// `j[key]` if it is an integer within [lo, hi]; Error naming `source` and the
// key otherwise (nlohmann's own exception when the key is missing).
inline int64_t JsonInt(const nlohmann::json& j, const char* key, int64_t lo, int64_t hi, const std::string& source) {
  const nlohmann::json& v = j.at(key);
  if (v.is_number_unsigned()) {
    const uint64_t u = v.get<uint64_t>();
    if (u <= static_cast<uint64_t>(hi) && static_cast<int64_t>(u) >= lo) return static_cast<int64_t>(u);
  } else if (v.is_number_integer()) {
    const int64_t i = v.get<int64_t>();
    if (i >= lo && i <= hi) return i;
  }
  throw FileError(source, std::string("'") + key + "' must be an integer from " + std::to_string(lo) + " to " +
                              std::to_string(hi) + ", not " + v.dump().substr(0, 40));
}

}  // namespace brdfshot

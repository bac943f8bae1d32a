// FNV-1a, 64-bit: the content fingerprint of probes, pixel geometries and
// shared basis images — it tells a changed input from the same one; it is not
// a cryptographic hash.
#pragma once

#include <cstddef>
#include <cstdint>

namespace brdfshot {

constexpr uint64_t kFnv1aOffset = 1469598103934665603ull;

// `h` continued over the `bytes` bytes at `data` (start from kFnv1aOffset).
inline uint64_t Fnv1a(const void* data, std::size_t bytes, uint64_t h = kFnv1aOffset) {
  const auto* b = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < bytes; ++i) h = (h ^ b[i]) * 1099511628211ull;
  return h;
}

}  // namespace brdfshot

// libFuzzer targets: the bytes of one input, as the readers see them. Readers
// that take a path get a per-process temporary file with the extension that
// selects their decoder. Every target accepts brdfshot::Error (a clear refusal)
// and nothing else: any other exception, crash or sanitizer report is a bug.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>

namespace brdfshot::fuzz {

inline std::string WriteTemp(const uint8_t* data, size_t size, const std::string& ext) {
  const std::string path = "/tmp/brdfshot_fuzz_" + std::to_string(getpid()) + ext;
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) __builtin_trap();  // the harness itself failed: not the reader's bug
  if (size) std::fwrite(data, 1, size, f);
  std::fclose(f);
  return path;
}

inline std::string Bytes(const uint8_t* data, size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

}  // namespace brdfshot::fuzz

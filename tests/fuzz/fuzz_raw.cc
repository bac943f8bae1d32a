// The RAW path of a bracket frame (libraw), as a DNG.
#include "capture/raw.h"
#include "tests/fuzz/fuzz_input.h"
#include "util/check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    brdfshot::ReadRaw(brdfshot::fuzz::WriteTemp(data, size, ".dng"));
  } catch (const brdfshot::Error&) {
  }
  return 0;
}

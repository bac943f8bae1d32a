// Observation files (.bsobs): tagged header + per-pixel records.
#include "normals/observation.h"
#include "tests/fuzz/fuzz_input.h"
#include "util/check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    brdfshot::Observations::Parse(brdfshot::fuzz::Bytes(data, size), "fuzz.bsobs");
  } catch (const brdfshot::Error&) {
  }
  return 0;
}

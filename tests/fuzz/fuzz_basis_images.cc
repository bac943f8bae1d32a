// The basis-image cache (.bsbi): tagged header + geometry + Y (+ the analytic lobes L).
#include "fit/basis_images.h"
#include "tests/fuzz/fuzz_input.h"
#include "util/check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    brdfshot::BasisImages::Parse(brdfshot::fuzz::Bytes(data, size), "fuzz.bsbi");
  } catch (const brdfshot::Error&) {
  }
  return 0;
}

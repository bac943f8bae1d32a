// MERL .binary tables (header, 3 × n doubles).
#include "fit/merl_brdf.h"
#include "tests/fuzz/fuzz_input.h"
#include "util/check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    brdfshot::MerlBrdf::Read(brdfshot::fuzz::WriteTemp(data, size, ".binary"));
  } catch (const brdfshot::Error&) {
  }
  return 0;
}

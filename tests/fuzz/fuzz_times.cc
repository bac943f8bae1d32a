// Exposure-times files and the exposure-time syntax ("1/250", "0.004", "2s").
#include "capture/exposure.h"
#include "tests/fuzz/fuzz_input.h"
#include "util/check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    brdfshot::ReadTimesFile(brdfshot::fuzz::WriteTemp(data, size, ".txt"));
  } catch (const brdfshot::Error&) {
  }
  try {
    brdfshot::ParseExposureTime(brdfshot::fuzz::Bytes(data, size), "fuzz");
  } catch (const brdfshot::Error&) {
  }
  return 0;
}

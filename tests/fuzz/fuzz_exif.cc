// The EXIF path of a bracket frame (exiv2), JPEG container.
#include "capture/exposure.h"
#include "tests/fuzz/fuzz_input.h"
#include "util/check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    brdfshot::ReadExif(brdfshot::fuzz::WriteTemp(data, size, ".jpg"));
  } catch (const brdfshot::Error&) {
  }
  return 0;
}

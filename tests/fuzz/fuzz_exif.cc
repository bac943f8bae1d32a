// A bracket frame's JPEG container: its EXIF (exiv2) and the walk of its
// markers that refuses a file cut short (util/jpeg_structure.h).
#include "capture/exposure.h"
#include "tests/fuzz/fuzz_input.h"
#include "util/check.h"
#include "util/jpeg_structure.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = brdfshot::fuzz::WriteTemp(data, size, ".jpg");
  try {
    brdfshot::ReadExif(path);
  } catch (const brdfshot::Error&) {
  }
  try {
    brdfshot::CheckJpegComplete(path);
  } catch (const brdfshot::Error&) {
  }
  return 0;
}

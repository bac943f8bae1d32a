// Light probes: EXR (OpenEXR), Radiance HDR and PFM (OpenCV), picked by the first byte.
#include "calib/latlong_probe.h"
#include "tests/fuzz/fuzz_input.h"
#include "util/check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const char* kExt[3] = {".exr", ".hdr", ".pfm"};
  try {
    brdfshot::LatLongProbe::Read(brdfshot::fuzz::WriteTemp(data + 1, size - 1, kExt[data[0] % 3]));
  } catch (const brdfshot::Error&) {
  }
  return 0;
}

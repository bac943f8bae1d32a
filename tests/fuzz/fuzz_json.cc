// The JSON files the stages read: class model, sphere file, response curve,
// merge sidecar (and calib's scale from exposure metadata), calibration —
// through the same file reader the commands use (ReadJsonFile).
#include "calib/calibration.h"
#include "calib/radiometric_scale.h"
#include "capture/merge_sidecar.h"
#include "capture/response.h"
#include "fit/class_model.h"
#include "normals/sphere_view.h"
#include "tests/fuzz/fuzz_input.h"
#include "util/atomic_file.h"
#include "util/check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = brdfshot::fuzz::WriteTemp(data, size, ".json");
  nlohmann::json j;
  try {
    j = brdfshot::ReadJsonFile(path);
  } catch (const brdfshot::Error&) {
    return 0;
  }
  try {
    brdfshot::ClassModel::FromJson(j, path);
  } catch (const brdfshot::Error&) {
  }
  try {
    brdfshot::SphereView::FromJson(j, path);
  } catch (const brdfshot::Error&) {
  }
  try {
    brdfshot::ResponseCurve::FromJson(j, path);
  } catch (const brdfshot::Error&) {
  }
  try {
    brdfshot::MergeSidecar::FromJson(j, path).WhiteBalance(path);
  } catch (const brdfshot::Error&) {
  }
  try {
    brdfshot::Calibration::FromJson(j, path);
  } catch (const brdfshot::Error&) {
  }
  try {
    brdfshot::ScaleFromMergeSidecars(j, path, j, path);
  } catch (const brdfshot::Error&) {
  }
  return 0;
}

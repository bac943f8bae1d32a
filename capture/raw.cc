#include "capture/raw.h"

#include <libraw/libraw.h>

#include <filesystem>
#include <memory>

#include "util/check.h"

namespace brdfshot {

namespace {
// One LibRaw per thread, recycled between files (LibRaw's documented reuse
// path): its constructor zeroes megabytes of tables, and on fresh pages that
// was most of the time of reading a small file (60 % page faults in the RAW
// fuzzer). recycle() on the way out frees the file's buffers.
LibRaw& Processor() {
  thread_local std::unique_ptr<LibRaw> p = std::make_unique<LibRaw>();
  return *p;
}
struct Recycle {
  LibRaw* raw;
  ~Recycle() { raw->recycle(); }
};

// LibRaw reports corrupt sensor data through this callback (by default it
// prints "data corrupted at N" and goes on, filling the frame with garbage):
// recorded here, it fails the read instead.
void RecordDataError(void* data, const char* /*file*/, const int offset) {
  int* first = static_cast<int*>(data);
  if (*first < 0) *first = offset;
}

// More sensor pixels than this per byte of file cannot be real data, however
// compressed (lossless RAW is ≥ 1 byte per pixel): a corrupt header.
constexpr double kMaxPixelsPerByte = 64;
}  // namespace

RawFrame ReadRaw(const std::string& path, const std::array<double, 3>* wb) {
  LibRaw* raw = &Processor();
  const Recycle recycle{raw};
  auto check = [&](int rc, const char* what) {
    if (rc != LIBRAW_SUCCESS) throw FileError(path, std::string(what) + ": " + libraw_strerror(rc));
  };
  int corrupt_at = -1;
  raw->set_dataerror_handler(RecordDataError, &corrupt_at);
  check(raw->open_file(path.c_str()), "cannot open RAW");
  const auto& sizes = raw->imgdata.sizes;
  const double pixels = double(sizes.raw_width) * sizes.raw_height;
  std::error_code ec;
  const auto file_bytes = std::filesystem::file_size(path, ec);
  if (!ec && pixels > kMaxPixelsPerByte * double(file_bytes))
    throw FileError(path, "declares a " + std::to_string(sizes.raw_width) + "x" + std::to_string(sizes.raw_height) +
                              " sensor but holds " + std::to_string(file_bytes) + " bytes (truncated or corrupt)");
  check(raw->unpack(), "cannot unpack RAW");
  if (corrupt_at >= 0)
    throw FileError(path, "RAW data corrupted at byte " + std::to_string(corrupt_at) + " (truncated or damaged file)");
  auto& p = raw->imgdata.params;
  p.gamm[0] = p.gamm[1] = 1.0;  // linear
  p.no_auto_bright = 1;
  p.output_bps = 16;
  p.output_color = 1;  // sRGB primaries, linear
  if (wb) {
    p.use_camera_wb = 0;
    for (int c = 0; c < 3; ++c) p.user_mul[c] = static_cast<float>((*wb)[c]);
    p.user_mul[3] = static_cast<float>((*wb)[1]);
  } else {
    p.use_camera_wb = 1;
    for (float& m : p.user_mul) m = 0;  // a previous file's --wb must not carry over
  }
  check(raw->dcraw_process(), "cannot process RAW");
  if (corrupt_at >= 0)
    throw FileError(path, "RAW data corrupted at byte " + std::to_string(corrupt_at) + " (truncated or damaged file)");
  int err = 0;
  libraw_processed_image_t* img = raw->dcraw_make_mem_image(&err);
  if (!img) check(err, "cannot make image");
  std::unique_ptr<libraw_processed_image_t, void (*)(libraw_processed_image_t*)> guard(img, LibRaw::dcraw_clear_mem);
  if (img->type != LIBRAW_IMAGE_BITMAP || img->colors != 3 || img->bits != 16)
    throw FileError(path, "libraw returned an unexpected image layout");
  RawFrame f;
  f.rgb16 = cv::Mat(img->height, img->width, CV_16UC3, img->data).clone();
  const auto& color = raw->imgdata.color;
  f.black = color.black;
  f.white = color.maximum;
  for (int c = 0; c < 3; ++c) f.wb[c] = wb ? (*wb)[c] : color.cam_mul[c] / std::max(1e-9f, color.cam_mul[1]);
  f.exposure_time = raw->imgdata.other.shutter;
  f.f_number = raw->imgdata.other.aperture;
  f.iso = raw->imgdata.other.iso_speed;
  f.focal_35mm = raw->imgdata.lens.FocalLengthIn35mmFormat;
  f.camera = std::string(raw->imgdata.idata.make) + " " + raw->imgdata.idata.model;
  return f;
}

}  // namespace brdfshot

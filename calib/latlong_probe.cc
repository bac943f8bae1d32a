#include "calib/latlong_probe.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "util/check.h"
#include "util/fnv_hash.h"
#include "util/image_io.h"

namespace brdfshot {

LatLongProbe::LatLongProbe(cv::Mat rgb, std::string name) : rgb_(std::move(rgb)), name_(std::move(name)) {
  BRDFSHOT_CHECK(rgb_.type() == CV_32FC3, "probe must be CV_32FC3");
  BRDFSHOT_CHECK(rgb_.cols == 2 * rgb_.rows && rgb_.rows >= 1,
                 "probe must be 2:1, got " << rgb_.cols << "x" << rgb_.rows);
}

LatLongProbe LatLongProbe::Read(const std::string& path) {
  cv::Mat rgb = ReadHdrImage(path);
  if (rgb.cols != 2 * rgb.rows)
    throw FileError(
        path, "not a lat-long probe: " + std::to_string(rgb.cols) + "x" + std::to_string(rgb.rows) + " is not 2:1");
  // Lossy EXR compression (DWA, as in the Poly Haven probes) rings slightly below
  // zero next to bright sources; radiance cannot be negative, so clamp.
  cv::max(rgb, 0.0f, rgb);
  return LatLongProbe(rgb, std::filesystem::path(path).stem().string());
}

namespace {
// Bilinear read of a lat-long image at (u, v) ∈ [0, 1]², wrapping in longitude
// and clamping at the poles: the one texel read of plain and prefiltered probes.
// Forced inline: it is the basis-image inner loop (4 calls per trilinear
// lookup), and with three callers GCC would otherwise keep it out of line.
[[gnu::always_inline]] inline cv::Vec3f BilinearLatLong(const cv::Mat& m, double u, double v) {
  const double x = u * m.cols - 0.5, y = v * m.rows - 0.5;
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const float fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
  // u ∈ [0, 1] so x0 ∈ [−1, cols]: wrap by comparison, not by division.
  const int xa = x0 < 0 ? x0 + m.cols : (x0 >= m.cols ? x0 - m.cols : x0);
  const int xb = xa + 1 == m.cols ? 0 : xa + 1;
  const int ya = std::clamp(y0, 0, m.rows - 1), yb = std::clamp(y0 + 1, 0, m.rows - 1);
  const cv::Vec3f* ra = m.ptr<cv::Vec3f>(ya);
  const cv::Vec3f* rb = m.ptr<cv::Vec3f>(yb);
  return (ra[xa] * (1 - fx) + ra[xb] * fx) * (1 - fy) + (rb[xa] * (1 - fx) + rb[xb] * fx) * fy;
}
}  // namespace

cv::Vec3f LatLongProbe::Bilinear(const Vec3& dir) const {
  double col, row;
  PixelAt(dir, &col, &row);
  return BilinearLatLong(rgb_, col / width(), row / height());
}

cv::Vec3f PrefilteredProbe::Bilinear(int level, double u, double v) const {
  return BilinearLatLong(levels_[level], u, v);
}

Vec3 LatLongProbe::DirectionAt(double col, double row) const {
  const double theta = kPi * row / height(), phi = 2 * kPi * col / width();
  const double s = std::sin(theta);
  return {-s * std::sin(phi), std::cos(theta), s * std::cos(phi)};
}

void LatLongProbe::PixelAt(const Vec3& d, double* col, double* row) const {
  const double theta = std::acos(std::clamp(d.y, -1.0, 1.0));
  double phi = std::atan2(-d.x, d.z);
  if (phi < 0) phi += 2 * kPi;
  *col = phi / (2 * kPi) * width();
  *row = theta / kPi * height();
}

double LatLongProbe::TexelSolidAngle(int row) const {
  const double t0 = kPi * row / height(), t1 = kPi * (row + 1) / height();
  return 2 * kPi / width() * (std::cos(t0) - std::cos(t1));
}

LatLongProbe LatLongProbe::Resized(int new_width) const {
  BRDFSHOT_CHECK(new_width >= 2 && new_width % 2 == 0);
  if (new_width == width()) return *this;
  const int new_h = new_width / 2;
  cv::Mat out(new_h, new_width, CV_32FC3, cv::Scalar::all(0));
  // Each output texel averages the source texels whose centres fall inside it,
  // weighted by their solid angle; fine for downsampling, nearest for upsampling.
  cv::Mat wsum(new_h, new_width, CV_64F, cv::Scalar(0));
  cv::Mat acc(new_h, new_width, CV_64FC3, cv::Scalar::all(0));
  for (int r = 0; r < height(); ++r) {
    const double w = TexelSolidAngle(r);
    const int rr = std::min(new_h - 1, static_cast<int>((r + 0.5) * new_h / height()));
    for (int c = 0; c < width(); ++c) {
      const int cc = std::min(new_width - 1, static_cast<int>((c + 0.5) * new_width / width()));
      const cv::Vec3f p = Texel(c, r);
      acc.at<cv::Vec3d>(rr, cc) += cv::Vec3d(p[0], p[1], p[2]) * w;
      wsum.at<double>(rr, cc) += w;
    }
  }
  for (int r = 0; r < new_h; ++r)
    for (int c = 0; c < new_width; ++c) {
      double w = wsum.at<double>(r, c);
      cv::Vec3d a = acc.at<cv::Vec3d>(r, c);
      if (w == 0) {  // upsampling: take the nearest source texel
        const int sr = std::min(height() - 1, static_cast<int>((r + 0.5) * height() / new_h));
        const int sc = std::min(width() - 1, static_cast<int>((c + 0.5) * width() / new_width));
        const cv::Vec3f p = Texel(sc, sr);
        a = cv::Vec3d(p[0], p[1], p[2]);
        w = 1;
      }
      out.at<cv::Vec3f>(r, c) = cv::Vec3f(a[0] / w, a[1] / w, a[2] / w);
    }
  return LatLongProbe(out, name_ + "@" + std::to_string(new_width));
}

LatLongProbe LatLongProbe::Rotated(const Rotation& to_this) const {
  cv::Mat img(height(), width(), CV_32FC3);
  for (int r = 0; r < img.rows; ++r)
    for (int c = 0; c < img.cols; ++c) img.at<cv::Vec3f>(r, c) = Bilinear(to_this(DirectionAt(c + 0.5, r + 0.5)));
  return LatLongProbe(img, name_ + "@rotated");
}

uint64_t LatLongProbe::Hash() const {
  const cv::Mat c = rgb_.isContinuous() ? rgb_ : rgb_.clone();
  return Fnv1a(c.ptr<unsigned char>(), c.total() * c.elemSize());
}

PrefilteredProbe::PrefilteredProbe(const LatLongProbe& probe) {
  levels_.push_back(probe.rgb());
  texel0_omega_ = 4 * kPi / (static_cast<double>(probe.width()) * probe.height());
  // Halve until the map is 2x1; rows are averaged with their solid-angle weights.
  while (levels_.back().rows > 1) {
    const cv::Mat& src = levels_.back();
    const int h = src.rows / 2, w = src.cols / 2;
    cv::Mat dst(h, w, CV_32FC3);
    for (int r = 0; r < h; ++r) {
      const double t0 = kPi * (2 * r) / src.rows, t1 = kPi * (2 * r + 1) / src.rows, t2 = kPi * (2 * r + 2) / src.rows;
      const double w0 = std::cos(t0) - std::cos(t1), w1 = std::cos(t1) - std::cos(t2);
      for (int c = 0; c < w; ++c) {
        const cv::Vec3f a = src.at<cv::Vec3f>(2 * r, 2 * c) + src.at<cv::Vec3f>(2 * r, 2 * c + 1);
        const cv::Vec3f b = src.at<cv::Vec3f>(2 * r + 1, 2 * c) + src.at<cv::Vec3f>(2 * r + 1, 2 * c + 1);
        dst.at<cv::Vec3f>(r, c) = (a * w0 + b * w1) / (2 * (w0 + w1));
      }
    }
    levels_.push_back(dst);
  }
  for (const cv::Mat& m : levels_) {
    PaddedLevel pl{m.cols, m.rows, std::vector<float>(3 * static_cast<size_t>(m.cols + 2) * (m.rows + 2))};
    for (int pr = 0; pr < m.rows + 2; ++pr) {
      const cv::Vec3f* src = m.ptr<cv::Vec3f>(std::clamp(pr - 1, 0, m.rows - 1));
      float* dst = pl.rgb.data() + 3 * static_cast<size_t>(pr) * (m.cols + 2);
      for (int pc = 0; pc < m.cols + 2; ++pc) {
        const cv::Vec3f& t = src[(pc - 1 + m.cols) % m.cols];
        dst[3 * pc] = t[0], dst[3 * pc + 1] = t[1], dst[3 * pc + 2] = t[2];
      }
    }
    padded_.push_back(std::move(pl));
  }
}

namespace {
// atan2 to ~1e-6 rad (minimax polynomial on [0, 1]), several times faster than
// libm's: the probe lookup is the inner loop of every basis image, and a
// micro-radian is far below a texel (0.7° at 512 wide).
inline double FastAtan2(double y, double x) {
  const double ax = std::abs(x), ay = std::abs(y);
  const double mx = std::max(ax, ay), mn = std::min(ax, ay);
  if (mx == 0) return 0;
  const double z = mn / mx, z2 = z * z;
  double r = z * (0.99997726 +
                  z2 * (-0.33262347 + z2 * (0.19354346 + z2 * (-0.11643287 + z2 * (0.05265332 + z2 * (-0.01172120))))));
  if (ay > ax) r = kPi / 2 - r;
  if (x < 0) r = kPi - r;
  return y < 0 ? -r : r;
}
// The same polynomial in float and without branches, so that loops over
// arrays of directions vectorise.
inline float FastAtan2f(float y, float x) {
  const float ax = std::abs(x), ay = std::abs(y);
  const float mx = std::max(ax, ay), mn = std::min(ax, ay);
  const float z = mn / std::max(mx, 1e-30f), z2 = z * z;
  float r =
      z * (0.99997726f +
           z2 * (-0.33262347f + z2 * (0.19354346f + z2 * (-0.11643287f + z2 * (0.05265332f + z2 * (-0.01172120f))))));
  r = ay > ax ? 1.57079633f - r : r;
  r = x < 0 ? 3.14159265f - r : r;
  return std::copysign(r, y);
}

// log2 to ~1e-3 from the float's exponent and a cubic in its mantissa: it only
// picks a filter width, where 1e-3 of a level is invisible.
inline float FastLog2(float x) {
  uint32_t bits;
  std::memcpy(&bits, &x, 4);
  const float e = static_cast<float>(static_cast<int>(bits >> 23) - 127);
  bits = (bits & 0x7fffffu) | 0x3f800000u;
  float m;
  std::memcpy(&m, &bits, 4);
  const float t = m - 1;
  return e + t * (1.4425449f + t * (-0.7181452f + t * 0.2750526f));
}
}  // namespace

void PrefilteredProbe::Angles(const Vec3& d, double* u, double* v) {
  // Same frame as LatLongProbe::PixelAt: θ from +Y, φ from −Z towards −X.
  const double theta = FastAtan2(std::sqrt(d.x * d.x + d.z * d.z), d.y);
  double phi = FastAtan2(-d.x, d.z);
  if (phi < 0) phi += 2 * kPi;
  *u = phi / (2 * kPi);
  *v = theta / kPi;
}

cv::Vec3f PrefilteredProbe::LookupLevel(const Vec3& d, int level) const {
  double u, v;
  Angles(d, &u, &v);
  return Bilinear(level, u, v);
}

cv::Vec3f PrefilteredProbe::Trilinear(double u, double v, double lod) const {
  const int top = levels() - 1;
  if (lod <= 0) return Bilinear(0, u, v);
  if (lod >= top) return Bilinear(top, u, v);
  const int l0 = static_cast<int>(lod);
  const float t = static_cast<float>(lod - l0);
  return Bilinear(l0, u, v) * (1 - t) + Bilinear(l0 + 1, u, v) * t;
}

void PrefilteredProbe::LookupMany(int n, const float* d, const float* omega, float* scratch, float* rgb) const {
  float* u = scratch;
  float* v = scratch + n;
  float* lod = scratch + 2 * n;
  const float inv_texel = static_cast<float>(1 / texel0_omega_);
  for (int i = 0; i < n; ++i) {  // vectorised: no branches, no calls
    const float x = d[3 * i], y = d[3 * i + 1], z = d[3 * i + 2];
    const float phi = FastAtan2f(-x, z);
    u[i] = (phi < 0 ? phi + 6.28318531f : phi) * 0.159154943f;
    v[i] = FastAtan2f(std::sqrt(x * x + z * z), y) * 0.318309886f;
    lod[i] = 0.5f * FastLog2(std::max(omega[i], 1e-30f) * inv_texel);
  }
  const int top = levels() - 1;
  // Bilinear in one padded level, added to `out` with weight `w`. The clamps
  // only guard against directions that are not unit vectors (NaN included).
  auto add_bilinear = [this](int level, float uu, float vv, float w, float* out) {
    const PaddedLevel& L = padded_[level];
    const float x = std::min(std::max(-1.0f, uu * L.w - 0.5f), L.w - 0.5f);
    const float y = std::min(std::max(-1.0f, vv * L.h - 0.5f), L.h - 0.5f);
    const float xf = std::floor(x), yf = std::floor(y);
    const float fx = x - xf, fy = y - yf;
    const int stride = 3 * (L.w + 2);
    const float* a = L.rgb.data() + (static_cast<int>(yf) + 1) * stride + 3 * (static_cast<int>(xf) + 1);
    const float* b = a + stride;
    const float w00 = w * (1 - fx) * (1 - fy), w01 = w * fx * (1 - fy), w10 = w * (1 - fx) * fy, w11 = w * fx * fy;
    for (int k = 0; k < 3; ++k) out[k] += w00 * a[k] + w01 * a[3 + k] + w10 * b[k] + w11 * b[3 + k];
  };
  for (int i = 0; i < n; ++i) {
    float* out = rgb + 3 * i;
    out[0] = out[1] = out[2] = 0;
    if (omega[i] <= 0) continue;
    const float l = std::min(std::max(0.0f, lod[i]), static_cast<float>(top));
    const int l0 = std::min(static_cast<int>(l), top);
    const float t = l - l0;
    add_bilinear(l0, u[i], v[i], 1 - t, out);
    if (t > 0) add_bilinear(l0 + 1, u[i], v[i], t, out);
  }
}

cv::Vec3f PrefilteredProbe::Lookup(const Vec3& d, double omega) const {
  double u, v;
  Angles(d, &u, &v);
  return Trilinear(u, v, 0.5 * std::log2(std::max(omega, 1e-30) / texel0_omega_));
}

}  // namespace brdfshot

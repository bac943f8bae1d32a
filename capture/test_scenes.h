// Test helpers shared by capture's tests and benchmarks (not part of the library).
#pragma once

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace brdfshot {

// Radiance with structure at every scale from 2 px to a fifth of the image
// (octaves of blurred noise), as a scene has, over several decades.
inline cv::Mat TexturedRadiance(cv::Size size, uint64_t seed = 3) {
  cv::RNG rng(seed);
  cv::Mat log_e(size, CV_32FC3, cv::Scalar::all(0));
  const double coarsest = std::max(size.width, size.height) / 16.0;
  for (double sigma = 2; sigma < 2 * coarsest; sigma *= 3) {
    cv::Mat octave(size, CV_32FC3);
    rng.fill(octave, cv::RNG::UNIFORM, -0.5, 0.5);
    cv::GaussianBlur(octave, octave, cv::Size(0, 0), sigma);
    cv::Scalar mean, sd;
    cv::meanStdDev(octave.reshape(1), mean, sd);
    log_e += octave * (0.8 / sd[0]);
  }
  cv::Mat e;
  cv::exp(log_e, e);
  return e;
}

// A camera turned about its lens by (yaw, pitch, roll) degrees maps pixels by
// H = K R K⁻¹ (focal length f, principal point at the centre of `size`).
inline cv::Matx33d TurnedCamera(double yaw, double pitch, double roll, double f, cv::Size size) {
  const double a = yaw * CV_PI / 180, b = pitch * CV_PI / 180, c = roll * CV_PI / 180;
  const cv::Matx33d Ry(std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a));
  const cv::Matx33d Rx(1, 0, 0, 0, std::cos(b), -std::sin(b), 0, std::sin(b), std::cos(b));
  const cv::Matx33d Rz(std::cos(c), -std::sin(c), 0, std::sin(c), std::cos(c), 0, 0, 0, 1);
  const cv::Matx33d K(f, 0, size.width / 2.0, 0, f, size.height / 2.0, 0, 0, 1);
  return K * Rz * Rx * Ry * K.inv();
}

// A temporary folder of PNG frames (BGR on disk, as given) and their times
// file, removed with the object.
struct FrameFolder {
  std::filesystem::path dir;
  std::vector<std::string> files;
  std::string times;
  explicit FrameFolder(const std::string& name) : dir(std::filesystem::temp_directory_path() / name) {
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
  }
  ~FrameFolder() { std::filesystem::remove_all(dir); }
  void Add(const cv::Mat& bgr, double t) {
    const std::string f = (dir / ("f" + std::to_string(files.size()) + ".png")).string();
    cv::imwrite(f, bgr);
    files.push_back(f);
    times += std::to_string(t) + "\n";
    std::ofstream((dir / "times.txt").string()) << times;
  }
  std::string TimesPath() const { return (dir / "times.txt").string(); }
};

}  // namespace brdfshot

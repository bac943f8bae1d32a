// Progress on long work, to stderr, at most a few lines per second and only when
// asked for (apps enable it; tests and library users stay quiet).
#pragma once

#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>

namespace brdfshot {

class Progress {
 public:
  Progress(std::string what, size_t total, bool enabled)
      : what_(std::move(what)),
        total_(total),
        enabled_(enabled),
        start_(std::chrono::steady_clock::now()),
        last_(start_) {}
  void Step(size_t n = 1) {
    if (!enabled_) return;
    std::lock_guard<std::mutex> lock(mu_);
    done_ += n;
    const auto now = std::chrono::steady_clock::now();
    if (done_ < total_ && now - last_ < std::chrono::milliseconds(500)) return;
    last_ = now;
    const double s = std::chrono::duration<double>(now - start_).count();
    std::fprintf(stderr, "\r%s: %zu/%zu (%.1f s)%s", what_.c_str(), done_, total_, s, done_ >= total_ ? "\n" : "");
    std::fflush(stderr);
  }

 private:
  std::string what_;
  size_t total_, done_ = 0;
  bool enabled_;
  std::chrono::steady_clock::time_point start_, last_;
  std::mutex mu_;
};

// Wall-clock seconds since construction.
class Stopwatch {
 public:
  Stopwatch() : t0_(std::chrono::steady_clock::now()) {}
  double Seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count(); }

 private:
  std::chrono::steady_clock::time_point t0_;
};

}  // namespace brdfshot

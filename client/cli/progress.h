// One progress line for the command line's long work (boards detected, views rendered, frames
// replayed): "what done/total (p %), r/s, ~s left", redrawn in place on stderr at most five
// times a second, and nothing at all when stderr is not a terminal (logs and pipes stay clean).
#pragma once

#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <iomanip>
#include <iostream>
#include <string>

namespace monocle::cli {

class ProgressLine {
 public:
  // `show`: whether to draw at all (default: stderr is a terminal).
  ProgressLine(std::string what, uint64_t total, bool show = isatty(STDERR_FILENO) == 1)
      : what_(std::move(what)), total_(total), shown_(show) {}
  ~ProgressLine() { Done(); }
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  // A step without a count (e.g. "calibrating from 12 boards..." after the detection).
  void Message(const std::string& text) {
    if (!shown_) return;
    std::cerr << "\r\033[K" << text << std::flush;
    drawn_ = true;
  }

  void Update(uint64_t done) {
    if (!shown_) return;
    const auto now = std::chrono::steady_clock::now();
    if (done < total_ && now - last_ < std::chrono::milliseconds(200)) return;
    last_ = now;
    const double s = std::chrono::duration<double>(now - start_).count();
    const double rate = s > 0 ? static_cast<double>(done) / s : 0;
    std::cerr << "\r\033[K" << what_ << " " << done << "/" << total_ << " (" << std::fixed
              << std::setprecision(0) << (total_ > 0 ? 100.0 * done / total_ : 100.0) << " %)";
    if (done > 0 && rate > 0) {
      std::cerr << ", " << std::setprecision(1) << rate << "/s";
      if (done < total_)
        std::cerr << ", ~" << std::setprecision(0) << (total_ - done) / rate << " s left";
    }
    std::cerr << std::flush;
    drawn_ = true;
  }

  // Clears the line (before other output, and at the end).
  void Done() {
    if (shown_ && drawn_) std::cerr << "\r\033[K" << std::flush;
    drawn_ = false;
  }

 private:
  std::string what_;
  uint64_t total_;
  bool shown_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last_{};
};

}  // namespace monocle::cli

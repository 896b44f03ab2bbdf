#pragma once
// A one-line progress bar with rate and ETA on stderr. It draws only when
// stderr is a terminal and output is not quiet, so logs and pipes stay clean.
#include <chrono>
#include <cstdint>
#include <string>

namespace pb4u {

class Progress {
 public:
  Progress(std::string label, int64_t total, std::string unit = "it");
  ~Progress();
  // Advances by `n` and redraws at most ~10 times a second; `status` is shown after the bar.
  void step(int64_t n = 1, const std::string& status = "");
  void finish();

  // Global switch set by the CLI's -q flag.
  static void set_quiet(bool quiet);
  static bool enabled();

 private:
  void draw(bool force);
  std::string label_, unit_, status_;
  int64_t total_, done_ = 0;
  std::chrono::steady_clock::time_point start_, last_draw_;
  bool finished_ = false;
};

// "1h02m", "3m05s", "12s".
std::string format_duration(double seconds);

}  // namespace pb4u

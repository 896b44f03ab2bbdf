#pragma once
// A one-line progress bar with rate and ETA on stderr, redrawn in place when stderr is a
// terminal. Into a log or a pipe it writes nothing for work that ends within a minute, and a
// plain line a minute for longer work (a solver's rollouts take hours), then one when it ends.
// Nothing at all with -q.
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
  static bool enabled();  // drawing a bar: stderr is a terminal and not quiet
  // Seconds between the plain lines written when stderr is not a terminal (60; tests shorten it).
  static void set_log_interval(double seconds);

 private:
  void draw(bool force);
  void log_line(std::chrono::steady_clock::time_point now, bool done);
  std::string label_, unit_, status_;
  int64_t total_, done_ = 0;
  std::chrono::steady_clock::time_point start_, last_draw_, last_log_;
  bool finished_ = false, logged_ = false;
};

// "12.3 frame/s" or "4.56 s/frame" for `done` units in `elapsed` seconds.
std::string format_rate(int64_t done, double elapsed, const std::string& unit);

// "1h02m", "3m05s", "12s".
std::string format_duration(double seconds);

}  // namespace pb4u

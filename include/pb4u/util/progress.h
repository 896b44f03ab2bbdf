#pragma once
// A one-line progress bar with rate and ETA on stderr, redrawn in place when stderr is a
// terminal. Into a log or a pipe it writes nothing for work that ends within a minute, and a
// plain line a minute for longer work (a solver's rollouts take hours), then one when it ends.
// Nothing at all with -q. The ETA prices the units left at the recent cost of a unit (the
// last minute or so weighs most: unit_seconds_after), so that slow work after fast work, as a
// solver's frames after a network's, is not priced at the fast work's rate.
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
  double eta_seconds() const;
  std::chrono::steady_clock::time_point start_, last_draw_, last_log_, last_step_;
  double unit_seconds_ = -1;  // the recent cost of a unit (s); < 0 until a unit is done
  bool finished_ = false, logged_ = false;
};

// The recent cost of a unit after `n` more units took `seconds`: their cost per unit where there
// was none (previous < 0), else the previous estimate moved towards it by 1 - exp(-seconds /
// window): work of a window's length or more weighs most, a moment's work little.
double unit_seconds_after(double previous, double seconds, int64_t n, double window = 60);

// "12.3 frame/s" or "4.56 s/frame" for `done` units in `elapsed` seconds.
std::string format_rate(int64_t done, double elapsed, const std::string& unit);

// "1h02m", "3m05s", "12s".
std::string format_duration(double seconds);

}  // namespace pb4u

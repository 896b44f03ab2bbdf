#include "pb4u/util/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace pb4u {
namespace {
bool g_quiet = false;
double g_log_interval = 60;  // s
}

void Progress::set_quiet(bool quiet) { g_quiet = quiet; }
bool Progress::enabled() { return !g_quiet && ::isatty(STDERR_FILENO); }
void Progress::set_log_interval(double seconds) { g_log_interval = seconds; }

double unit_seconds_after(double previous, double seconds, int64_t n, double window) {
  if (n <= 0) return previous;
  const double cost = seconds / double(n);
  if (previous < 0) return cost;
  const double weight = 1 - std::exp(-seconds / window);
  return previous + weight * (cost - previous);
}

std::string format_rate(int64_t done, double elapsed, const std::string& unit) {
  const double rate = elapsed > 0 ? done / elapsed : 0.0;
  char buf[48];
  if (rate >= 1 || rate == 0)
    std::snprintf(buf, sizeof buf, "%.1f %s/s", rate, unit.c_str());
  else
    std::snprintf(buf, sizeof buf, "%.2f s/%s", 1.0 / rate, unit.c_str());
  return buf;
}

std::string format_duration(double s) {
  if (!std::isfinite(s) || s < 0) return "--";
  char buf[32];
  long t = std::lround(s);
  if (t >= 3600)
    std::snprintf(buf, sizeof buf, "%ldh%02ldm", t / 3600, (t % 3600) / 60);
  else if (t >= 60)
    std::snprintf(buf, sizeof buf, "%ldm%02lds", t / 60, t % 60);
  else
    std::snprintf(buf, sizeof buf, "%lds", t);
  return buf;
}

Progress::Progress(std::string label, int64_t total, std::string unit)
    : label_(std::move(label)), unit_(std::move(unit)), total_(std::max<int64_t>(total, 1)),
      start_(std::chrono::steady_clock::now()), last_draw_(start_), last_log_(start_), last_step_(start_) {
  draw(true);
}

Progress::~Progress() { finish(); }

void Progress::step(int64_t n, const std::string& status) {
  const auto now = std::chrono::steady_clock::now();
  unit_seconds_ = unit_seconds_after(unit_seconds_, std::chrono::duration<double>(now - last_step_).count(), n);
  last_step_ = now;
  done_ = std::min(total_, done_ + n);
  status_ = status;
  draw(done_ == total_);
}

void Progress::finish() {
  if (finished_) return;
  finished_ = true;
  if (g_quiet) return;
  if (!enabled()) {
    if (logged_) log_line(std::chrono::steady_clock::now(), true);
    return;
  }
  draw(true);
  std::fputc('\n', stderr);
  std::fflush(stderr);
}

// One plain line: "label: 34/120 frame (28%), 12.3 s/frame, ETA 17m38s, status"; at the end
// "label: 120/120 frame in 24m36s, 12.3 s/frame".
void Progress::log_line(std::chrono::steady_clock::time_point now, bool done) {
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const std::string rate = format_rate(done_, elapsed, unit_);
  if (done) {
    std::fprintf(stderr, "%s: %lld/%lld %s in %s, %s\n", label_.c_str(), static_cast<long long>(done_),
                 static_cast<long long>(total_), unit_.c_str(), format_duration(elapsed).c_str(), rate.c_str());
  } else {
    std::fprintf(stderr, "%s: %lld/%lld %s (%.0f%%), %s, ETA %s%s%s\n", label_.c_str(),
                 static_cast<long long>(done_), static_cast<long long>(total_), unit_.c_str(),
                 100.0 * double(done_) / double(total_), rate.c_str(),
                 format_duration(eta_seconds()).c_str(), status_.empty() ? "" : ", ",
                 status_.c_str());
  }
  std::fflush(stderr);
  last_log_ = now;
  logged_ = true;
}

double Progress::eta_seconds() const { return unit_seconds_ < 0 ? NAN : unit_seconds_ * double(total_ - done_); }

void Progress::draw(bool force) {
  if (g_quiet) return;
  auto now = std::chrono::steady_clock::now();
  if (!enabled()) {
    if (done_ > 0 && done_ < total_ && std::chrono::duration<double>(now - last_log_).count() >= g_log_interval)
      log_line(now, false);
    return;
  }
  if (!force && now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  double elapsed = std::chrono::duration<double>(now - start_).count();
  const double eta = eta_seconds();
  constexpr int kWidth = 24;
  int filled = static_cast<int>(kWidth * done_ / total_);
  std::string bar(filled, '#');
  bar.resize(kWidth, '.');
  std::fprintf(stderr, "\r\033[K%s [%s] %lld/%lld %s ETA %s %s", label_.c_str(), bar.c_str(),
               static_cast<long long>(done_), static_cast<long long>(total_),
               format_rate(done_, elapsed, unit_).c_str(), format_duration(eta).c_str(), status_.c_str());
  std::fflush(stderr);
}

}  // namespace pb4u

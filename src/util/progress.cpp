#include "pb4u/util/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace pb4u {
namespace {
bool g_quiet = false;
}

void Progress::set_quiet(bool quiet) { g_quiet = quiet; }
bool Progress::enabled() { return !g_quiet && ::isatty(STDERR_FILENO); }

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
      start_(std::chrono::steady_clock::now()), last_draw_(start_) {
  draw(true);
}

Progress::~Progress() { finish(); }

void Progress::step(int64_t n, const std::string& status) {
  done_ = std::min(total_, done_ + n);
  status_ = status;
  draw(done_ == total_);
}

void Progress::finish() {
  if (finished_) return;
  finished_ = true;
  if (!enabled()) return;
  draw(true);
  std::fputc('\n', stderr);
  std::fflush(stderr);
}

void Progress::draw(bool force) {
  if (!enabled()) return;
  auto now = std::chrono::steady_clock::now();
  if (!force && now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  double elapsed = std::chrono::duration<double>(now - start_).count();
  double rate = elapsed > 0 ? done_ / elapsed : 0.0;
  double eta = rate > 0 ? (total_ - done_) / rate : NAN;
  constexpr int kWidth = 24;
  int filled = static_cast<int>(kWidth * done_ / total_);
  std::string bar(filled, '#');
  bar.resize(kWidth, '.');
  char rate_buf[32];
  if (rate >= 1 || rate == 0)
    std::snprintf(rate_buf, sizeof rate_buf, "%.1f %s/s", rate, unit_.c_str());
  else
    std::snprintf(rate_buf, sizeof rate_buf, "%.2f s/%s", 1.0 / rate, unit_.c_str());
  std::fprintf(stderr, "\r\033[K%s [%s] %lld/%lld %s ETA %s %s", label_.c_str(), bar.c_str(),
               static_cast<long long>(done_), static_cast<long long>(total_), rate_buf,
               format_duration(eta).c_str(), status_.c_str());
  std::fflush(stderr);
}

}  // namespace pb4u

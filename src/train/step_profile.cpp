#include "pb4u/train/step_profile.h"

#include <algorithm>
#include <cstdio>

namespace pb4u {
namespace {

double median_of(std::vector<double> v) {
  if (v.empty()) return 0;
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + mid, v.end());
  if (v.size() % 2) return v[mid];
  const double upper = v[mid];
  return 0.5 * (upper + *std::max_element(v.begin(), v.begin() + mid));
}

}  // namespace

void StepProfile::begin_step() {
  step_totals_.push_back(0);
  for (auto& [stage, values] : per_step_) values.push_back(0);
  restart_clock();
}

void StepProfile::restart_clock() { clock_ = std::chrono::steady_clock::now(); }

void StepProfile::lap(const std::string& stage) {
  const auto now = std::chrono::steady_clock::now();
  add(stage, std::chrono::duration<double, std::milli>(now - clock_).count());
  clock_ = now;
}

void StepProfile::add(const std::string& stage, double ms) {
  if (step_totals_.empty()) begin_step();
  auto it = per_step_.find(stage);
  if (it == per_step_.end()) {
    order_.push_back(stage);
    it = per_step_.emplace(stage, std::vector<double>(step_totals_.size(), 0.0)).first;
  }
  it->second.back() += ms;
  step_totals_.back() += ms;
}

std::vector<StepProfile::Row> StepProfile::rows() const {
  std::vector<Row> out;
  for (const auto& stage : order_) {
    const auto& v = per_step_.at(stage);
    Row r;
    r.stage = stage;
    r.median_ms = median_of(v);
    for (double x : v) r.mean_ms += x;
    r.mean_ms /= double(std::max<size_t>(1, v.size()));
    out.push_back(r);
  }
  return out;
}

double StepProfile::median_step_ms() const { return median_of(step_totals_); }

std::string StepProfile::table() const {
  const auto all = rows();
  double total = 0;
  for (const auto& r : all) total += r.mean_ms;
  std::string out = "| stage | median ms/step | mean ms/step | share of mean |\n|---|---|---|---|\n";
  char line[256];
  for (const auto& r : all) {
    std::snprintf(line, sizeof line, "| %s | %.2f | %.2f | %.1f%% |\n", r.stage.c_str(), r.median_ms,
                  r.mean_ms, total > 0 ? 100.0 * r.mean_ms / total : 0.0);
    out += line;
  }
  std::snprintf(line, sizeof line, "| step (%lld steps) | %.2f | %.2f | 100%% |\n",
                static_cast<long long>(steps()), median_step_ms(), total);
  out += line;
  return out;
}

}  // namespace pb4u

#pragma once
// Where a training step's time goes (`pb4u train --profile`): wall-clock milliseconds per
// stage, recorded per step and reported as medians and means over the steps profiled.
// Stages are named by the trainer (graph build, encode, propagation, each physics term,
// backward, optimiser, ...); a stage a step did not run counts 0 ms for that step.
#include <chrono>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace pb4u {

class StepProfile {
 public:
  // Opens a step: laps and adds until the next begin_step belong to it.
  void begin_step();
  // Adds the milliseconds since the last lap (or begin_step) to `stage`, restarts the clock.
  void lap(const std::string& stage);
  // Adds `ms` to `stage` of the open step, without touching the clock.
  void add(const std::string& stage, double ms);
  // Restarts the clock without charging anything.
  void restart_clock();

  int64_t steps() const { return int64_t(step_totals_.size()); }
  // Per stage, in first-seen order: the median and mean ms per step.
  struct Row {
    std::string stage;
    double median_ms = 0, mean_ms = 0;
  };
  std::vector<Row> rows() const;
  double median_step_ms() const;
  // A Markdown table of rows() with each stage's share of the summed means, and a total row.
  std::string table() const;

 private:
  std::vector<std::string> order_;
  std::map<std::string, std::vector<double>> per_step_;  // ms per step, one entry per step
  std::vector<double> step_totals_;
  std::chrono::steady_clock::time_point clock_ = std::chrono::steady_clock::now();
};

}  // namespace pb4u

#pragma once
// <run>/metrics.jsonl: one JSON object per training step (SPEC 7: at least step, loss, lr,
// seconds and one key per active physics term). Lines are flushed as written so a killed
// run keeps every finished step.
#include <cstdint>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

namespace pb4u {

class MetricsLog {
 public:
  // Opens `path` for appending. With resume_step >= 0, first drops every line whose step is
  // greater than resume_step (they belong to work the resumed run will redo) and any line
  // that does not parse (the half-written last line of a killed run).
  MetricsLog(const std::string& path, int64_t resume_step);

  // Writes {"step": step, "<k>": v, ...} in the given order, one line, values to 9
  // significant digits. Non-finite values are written as null (JSON has no NaN).
  void write(int64_t step, const std::vector<std::pair<std::string, double>>& values);

 private:
  std::ofstream out_;
  std::string path_;
};

// Reads metrics.jsonl back as rows of (key, value) pairs in the file's order, "step" first;
// null reads as NaN. A last line cut short (a killed run) is skipped; any other line that is
// not a JSON object of numbers is a pb4u::Error naming the file and the line. Used by tests
// and plotting.
std::vector<std::vector<std::pair<std::string, double>>> read_metrics(const std::string& path);

}  // namespace pb4u

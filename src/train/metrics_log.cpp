#include "pb4u/train/metrics_log.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "pb4u/util/atomic_file.h"
#include "pb4u/util/error.h"
#include "pb4u/util/number_format.h"

namespace pb4u {
namespace {

using MetricsJson = nlohmann::ordered_json;  // keys in the order written

// The "step" of a metrics line, or -1 when the line is not a record with one (a line cut short
// by a killed run).
int64_t metrics_line_step(const std::string& line) {
  const MetricsJson record = MetricsJson::parse(line, nullptr, /*allow_exceptions=*/false);
  if (!record.is_object()) return -1;  // a parse error is "discarded", not an object
  const auto step = record.find("step");
  if (step == record.end() || !step->is_number()) return -1;
  return step->get<int64_t>();
}

// A value rounded to 9 significant digits ("%.9g"), so nlohmann's shortest round-trip form has
// the same digits; non-finite values are null (JSON has no NaN).
MetricsJson metric_figure(double v) {
  return std::isfinite(v) ? MetricsJson(round_to_significant(v, 9)) : MetricsJson(nullptr);
}

}  // namespace

MetricsLog::MetricsLog(const std::string& path, int64_t resume_step) : path_(path) {
  if (resume_step >= 0) {
    std::ifstream in(path);
    std::string line, kept;
    while (std::getline(in, line))
      if (int64_t s = metrics_line_step(line); s >= 0 && s <= resume_step) kept += line + "\n";
    AtomicFile file(path);
    file.stream() << kept;
    file.commit();
  }
  out_.open(path, std::ios::app);
  if (!out_) fail_file(path, "cannot open metrics log for writing");
}

void MetricsLog::write(int64_t step, const std::vector<std::pair<std::string, double>>& values) {
  MetricsJson record = {{"step", step}};
  for (const auto& [key, value] : values) record[key] = metric_figure(value);
  // One line, written at once: a killed run leaves at most the last line cut short.
  out_ << record.dump(-1, ' ', false, MetricsJson::error_handler_t::replace) + "\n";
  out_.flush();
  if (!out_) fail_file(path_, "cannot write metrics (disk full?)");
}

std::vector<std::vector<std::pair<std::string, double>>> read_metrics(const std::string& path) {
  std::ifstream in(path);
  if (!in) fail_file(path, "cannot read metrics log");
  std::vector<std::vector<std::pair<std::string, double>>> rows;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const bool cut_short = in.eof();  // the last line, without its newline
    const std::string where = "line " + std::to_string(number) + ": ";
    const MetricsJson record = MetricsJson::parse(line, nullptr, /*allow_exceptions=*/false);
    if (!record.is_object()) {
      if (cut_short) break;  // a killed run's half-written line
      fail_file(path, where + "not a JSON object");
    }
    std::vector<std::pair<std::string, double>> row;
    for (auto it = record.begin(); it != record.end(); ++it) {
      if (!it->is_number() && !it->is_null()) fail_file(path, where + "'" + it.key() + "' is not a number");
      row.emplace_back(it.key(), it->is_null() ? NAN : it->get<double>());
    }
    if (!row.empty()) rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace pb4u

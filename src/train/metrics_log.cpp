#include "pb4u/train/metrics_log.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "pb4u/util/atomic_file.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace {

// The step of a line we wrote: it always starts with {"step": N.
int64_t line_step(const std::string& line) {
  auto colon = line.find(':');
  if (line.rfind("{\"step\"", 0) != 0 || colon == std::string::npos) return -1;
  return std::atoll(line.c_str() + colon + 1);
}

}  // namespace

MetricsLog::MetricsLog(const std::string& path, int64_t resume_step) : path_(path) {
  if (resume_step >= 0) {
    std::ifstream in(path);
    std::string line, kept;
    while (std::getline(in, line))
      if (int64_t s = line_step(line); s >= 0 && s <= resume_step) kept += line + "\n";
    AtomicFile file(path);
    file.stream() << kept;
    file.commit();
  }
  out_.open(path, std::ios::app);
  if (!out_) fail_file(path, "cannot open metrics log for writing");
}

void MetricsLog::write(int64_t step, const std::vector<std::pair<std::string, double>>& values) {
  std::ostringstream line;
  line << "{\"step\": " << step;
  char buf[64];
  for (const auto& [key, value] : values) {
    if (std::isfinite(value))
      std::snprintf(buf, sizeof buf, "%.9g", value);
    else
      std::snprintf(buf, sizeof buf, "null");
    line << ", \"" << key << "\": " << buf;
  }
  line << "}\n";
  out_ << line.str();
  out_.flush();
  if (!out_) fail_file(path_, "cannot write metrics (disk full?)");
}

std::vector<std::vector<std::pair<std::string, double>>> read_metrics(const std::string& path) {
  std::ifstream in(path);
  if (!in) fail_file(path, "cannot read metrics log");
  std::vector<std::vector<std::pair<std::string, double>>> rows;
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::pair<std::string, double>> row;
    // Flat objects of "key": number|null pairs, as written above.
    size_t pos = 0;
    while ((pos = line.find('"', pos)) != std::string::npos) {
      size_t end = line.find('"', pos + 1);
      if (end == std::string::npos) break;
      std::string key = line.substr(pos + 1, end - pos - 1);
      size_t colon = line.find(':', end);
      if (colon == std::string::npos) break;
      const char* v = line.c_str() + colon + 1;
      while (*v == ' ') ++v;
      double value = std::strncmp(v, "null", 4) == 0 ? NAN : std::strtod(v, nullptr);
      row.emplace_back(key, value);
      pos = line.find_first_of(",}", colon);
      if (pos == std::string::npos) break;
    }
    if (!row.empty()) rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace pb4u

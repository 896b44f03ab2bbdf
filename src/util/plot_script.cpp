#include "pb4u/util/plot_script.h"

#include <spdlog/spdlog.h>

#include <cstdlib>

#include "pb4u/util/resource_dir.h"
#include "pb4u/util/subprocess.h"

namespace pb4u {
namespace {

bool imports_matplotlib(const std::string& python) {
  return run_process({python, "-c", "import matplotlib"}) == 0;
}

std::string find_plot_python() {
  if (const char* env = std::getenv("PB4U_PYTHON"); env && *env) return env;
  for (const auto& python : find_all_on_path("python3"))
    if (imports_matplotlib(python)) return python;
  return "";
}

}  // namespace

std::string plot_python() {
  static const std::string python = find_plot_python();
  return python;
}

bool run_plot_script(const std::string& script, const std::vector<std::string>& args) {
  const std::string path = resource_path("scripts/" + script);
  if (path.empty()) {
    spdlog::warn("no scripts/{} (pb4u's scripts are not beside the binary; set PB4U_DATA_DIR): no plot", script);
    return false;
  }
  const std::string python = plot_python();
  if (python.empty()) {
    spdlog::warn("no python3 with matplotlib on PATH (install python3-matplotlib, or set PB4U_PYTHON): no plot");
    return false;
  }
  std::vector<std::string> argv{python, path};
  argv.insert(argv.end(), args.begin(), args.end());
  if (run_process(argv) != 0) {
    spdlog::warn("{} {} failed (matplotlib missing?): no plot", python, script);
    return false;
  }
  return true;
}

}  // namespace pb4u

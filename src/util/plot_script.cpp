#include "pb4u/util/plot_script.h"

#include <spdlog/spdlog.h>

#include <cstdlib>
#include <filesystem>

namespace pb4u {

bool run_plot_script(const std::string& script, const std::vector<std::string>& args) {
  const std::string python = "/usr/bin/python3";
  const std::string path = std::string(PB4U_SOURCE_DIR) + "/scripts/" + script;
  if (!std::filesystem::exists(python) || !std::filesystem::exists(path)) {
    spdlog::warn("no {} or {}: skipping the plot", python, path);
    return false;
  }
  std::string cmd = python + " '" + path + "'";
  for (const auto& a : args) cmd += " '" + a + "'";
  cmd += " > /dev/null 2>&1";
  if (std::system(cmd.c_str()) != 0) {
    spdlog::warn("{} failed (matplotlib missing?): no plot", script);
    return false;
  }
  return true;
}

}  // namespace pb4u

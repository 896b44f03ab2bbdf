#pragma once
// Figures are drawn by the Python scripts in scripts/ (matplotlib, Debian's /usr/bin/python3).
#include <string>
#include <vector>

namespace pb4u {

// Runs scripts/<script> with `args` (single-quoted) under /usr/bin/python3, output discarded.
// Returns false, with a warning naming what is missing or failed, when Python, the script or
// matplotlib is not there: a figure is never worth failing the command for.
bool run_plot_script(const std::string& script, const std::vector<std::string>& args);

}  // namespace pb4u

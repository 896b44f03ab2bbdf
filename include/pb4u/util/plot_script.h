#pragma once
// Figures are drawn by the Python scripts in pb4u's scripts/ (util/resource_dir.h) with
// matplotlib, under the Python plot_python() finds.
#include <string>
#include <vector>

namespace pb4u {

// The Python that draws figures: $PB4U_PYTHON when set; otherwise the first python3 on PATH
// that imports matplotlib (Debian's python3-matplotlib lives under the system python3, which
// need not be the first python3 on PATH). "" when there is none. Looked up once per process.
std::string plot_python();

// Runs scripts/<script> with `args` (an argument vector, no shell) under plot_python(), its
// output discarded. Returns false, with a warning naming what is missing or failed, when the
// script, Python or matplotlib is not there: a figure is never worth failing the command for.
bool run_plot_script(const std::string& script, const std::vector<std::string>& args);

}  // namespace pb4u

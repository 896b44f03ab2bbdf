#pragma once
// Child processes (Python plots, Blender's cloth) started with an argument vector, never
// through a shell: no quoting, and a path with spaces or quotes is passed as it is.
#include <string>
#include <vector>

namespace pb4u {

// Runs argv[0] (searched on PATH when it holds no '/') with arguments argv[1..], waits, and
// returns its exit status: 0..255, 127 when it could not be started, 128 + N when signal N
// ended it. stdout and stderr both go to `output_path` (created or truncated), or are
// discarded when it is empty.
int run_process(const std::vector<std::string>& argv, const std::string& output_path = "");

// The full path of every executable file called `name` in the directories of PATH, in PATH's
// order (duplicates removed); empty when there is none.
std::vector<std::string> find_all_on_path(const std::string& name);

}  // namespace pb4u

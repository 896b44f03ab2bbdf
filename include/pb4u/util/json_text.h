#pragma once
// The two pieces of hand-written JSON output: a quoted, escaped string and a number
// (9 significant digits; non-finite values become null). Shared by evaluate and score.
#include <string>

namespace pb4u {

std::string json_string(const std::string& s);
std::string json_number(double v);

}  // namespace pb4u

#pragma once
// One exception type for every user-facing failure. Its message is the single
// line the CLI prints: it names the file or config key at fault.
#include <stdexcept>
#include <string>

namespace pb4u {

struct Error : std::runtime_error {
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

// "path: message" — the shape of every file-related error.
[[noreturn]] void fail_file(const std::string& path, const std::string& message);

}  // namespace pb4u

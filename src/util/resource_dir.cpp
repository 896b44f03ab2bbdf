#include "pb4u/util/resource_dir.h"

#include <spdlog/spdlog.h>

#include <cstdlib>
#include <filesystem>

namespace pb4u {
namespace {

namespace fs = std::filesystem;

// A directory holds pb4u's resources when its scripts/ has the preview script.
bool holds_resources(const fs::path& dir) {
  std::error_code ec;
  return fs::is_regular_file(dir / "scripts" / "plot_preview.py", ec);
}

std::string find_resource_dir() {
  if (const char* env = std::getenv("PB4U_DATA_DIR"); env && *env) {
    if (holds_resources(env)) return fs::path(env).lexically_normal().string();
    spdlog::warn("PB4U_DATA_DIR={} holds no scripts/plot_preview.py: ignored", env);
  }
  const std::string exe = executable_dir();
  if (exe.empty()) return "";
  // Walk up from the binary: <prefix>/bin -> <prefix>/share/pb4u, or a checkout above a
  // build directory (tests' binaries sit a few levels down in it).
  fs::path dir = exe;
  for (int up = 0; up < 5 && !dir.empty(); ++up) {
    if (holds_resources(dir / "share" / "pb4u")) return (dir / "share" / "pb4u").string();
    if (holds_resources(dir)) return dir.string();
    if (dir == dir.parent_path()) break;
    dir = dir.parent_path();
  }
  return "";
}

}  // namespace

std::string executable_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : exe.parent_path().string();
}

std::string resource_dir() {
  static const std::string dir = find_resource_dir();
  return dir;
}

std::string resource_path(const std::string& relative) {
  const std::string dir = resource_dir();
  if (dir.empty()) return "";
  std::error_code ec;
  const fs::path p = fs::path(dir) / relative;
  return fs::exists(p, ec) ? p.string() : std::string();
}

}  // namespace pb4u

#include "pb4u/util/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <filesystem>

#include "pb4u/util/error.h"

namespace pb4u {
namespace fs = std::filesystem;

std::string temp_path_for(const std::string& path) {
  return path + ".tmp." + std::to_string(::getpid());
}

AtomicFile::AtomicFile(std::string path, bool binary)
    : path_(std::move(path)), temp_(temp_path_for(path_)) {
  out_.open(temp_, binary ? std::ios::out | std::ios::binary | std::ios::trunc
                          : std::ios::out | std::ios::trunc);
  if (!out_) fail_file(path_, std::string("cannot write: ") + std::strerror(errno));
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    out_.close();
    std::remove(temp_.c_str());
  }
}

void AtomicFile::commit() {
  out_.flush();
  if (!out_) fail_file(path_, "write failed (disk full?)");
  out_.close();
  commit_file(temp_, path_);
  committed_ = true;
}

void commit_file(const std::string& temp_path, const std::string& path) {
  int fd = ::open(temp_path.c_str(), O_RDONLY);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
  if (std::rename(temp_path.c_str(), path.c_str()) != 0) {
    std::string reason = std::strerror(errno);
    std::remove(temp_path.c_str());
    fail_file(path, "cannot replace: " + reason);
  }
}

void ensure_output_dir(const std::string& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    fail_file(dir, "output directory is an existing file");
  fs::create_directories(dir, ec);
  if (ec) fail_file(dir, "cannot create output directory: " + ec.message());
  if (::access(dir.c_str(), W_OK) != 0) fail_file(dir, "output directory is not writable");
}

}  // namespace pb4u

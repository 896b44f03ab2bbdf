#include "pb4u/util/remove_tree.h"

#include <ftw.h>
#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "pb4u/util/error.h"

namespace pb4u {
namespace {

// nftw's callback takes no context: the walk's state is per thread.
thread_local std::uintmax_t removed = 0;
thread_local std::string failed_path;
thread_local int failed_errno = 0;

int remove_entry(const char* path, const struct stat*, int, struct FTW*) {
  if (std::remove(path) != 0) {  // unlink for files and links, rmdir for (now empty) directories
    failed_path = path;
    failed_errno = errno;
    return 1;  // stops the walk
  }
  ++removed;
  return 0;
}

}  // namespace

std::uintmax_t remove_tree(const std::string& path) {
  struct stat st;
  if (::lstat(path.c_str(), &st) != 0) {
    if (errno == ENOENT) return 0;
    fail_file(path, std::string("cannot remove: ") + std::strerror(errno));
  }
  removed = 0;
  failed_path.clear();
  failed_errno = 0;
  // FTW_DEPTH: a directory after its contents; FTW_PHYS: links are entries, not followed.
  const int status = ::nftw(path.c_str(), remove_entry, 16, FTW_DEPTH | FTW_PHYS);
  if (status != 0) {
    if (!failed_path.empty()) fail_file(failed_path, std::string("cannot remove: ") + std::strerror(failed_errno));
    fail_file(path, std::string("cannot remove: ") + std::strerror(errno));
  }
  return removed;
}

}  // namespace pb4u

#pragma once
// Writes a file so that readers see either the old content or the complete new
// one, never a partial file: data goes to "<path>.tmp.<pid>" and is renamed over
// <path> only on commit(). A writer destroyed without commit() removes its
// temporary and leaves <path> untouched.
#include <fstream>
#include <string>

namespace pb4u {

class AtomicFile {
 public:
  explicit AtomicFile(std::string path, bool binary = false);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ostream& stream() { return out_; }
  const std::string& temp_path() const { return temp_; }
  // Flushes, fsyncs and renames onto the final path. Throws pb4u::Error on failure.
  void commit();

 private:
  std::string path_, temp_;
  std::ofstream out_;
  bool committed_ = false;
};

// Atomically replaces `path` with the file at `temp_path` (fsync + rename).
void commit_file(const std::string& temp_path, const std::string& path);

// Temporary path next to `path` that commit_file() can rename into place.
std::string temp_path_for(const std::string& path);

// Creates directory `dir` (and parents); fails clearly if it is a file or not writable.
void ensure_output_dir(const std::string& dir);

}  // namespace pb4u

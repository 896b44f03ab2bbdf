#pragma once
// The one HDF5 layer under every pb4u .h5 file (datasets, rollout.h5, model exports): open or
// atomically write a file, walk its groups, read and write row-major n-D datasets of float64,
// float32, int32 or int64 and 1-D lists of fixed-length strings, and scalar attributes. Every
// failure is a one-line pb4u::Error "<file>: <object>: <reason>"; HDF5 itself stays out of
// this header.
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace pb4u {

// A group of an open HDF5 file ("/" is the root group). Copies share the file, which stays
// open while any copy lives.
class Hdf5Group {
 public:
  struct State;  // defined in hdf5_file.cpp
  explicit Hdf5Group(std::shared_ptr<State> state);

  const std::string& file() const;  // the path errors name (the final path while writing)
  const std::string& name() const;  // the group's path in the file: "/", "/bodies/alice"
  // "<name>/<child>" ("/<child>" under the root): how errors name a child.
  std::string child_path(const std::string& child) const;

  // ---- children (groups and datasets) ----
  bool has(const std::string& child) const;
  std::vector<std::string> children() const;  // in name order
  // The child group; a missing one is "<file>: <name>/<child>: missing".
  Hdf5Group group(const std::string& child) const;
  Hdf5Group create_group(const std::string& child);

  // ---- datasets (row-major) ----
  // The dataset's dimensions; a missing one is "<file>: <name>/<dataset>: missing".
  std::vector<size_t> shape(const std::string& dataset) const;
  // Reads the whole dataset, converted to the type of `out`, which holds product(shape) values.
  void read(const std::string& dataset, double* out) const;
  void read(const std::string& dataset, float* out) const;
  void read(const std::string& dataset, int32_t* out) const;
  void read(const std::string& dataset, int64_t* out) const;
  // Creates dataset `name` of the given shape, stored as the type of `data` (float64, float32,
  // int32, int64), from product(shape) values. `compress`: arrays of at least 4096 values are
  // chunked along the first axis (about 64 Ki values a chunk) and deflated at level 4.
  void write(const std::string& name, const std::vector<size_t>& shape, const double* data,
             bool compress = false);
  void write(const std::string& name, const std::vector<size_t>& shape, const float* data,
             bool compress = false);
  void write(const std::string& name, const std::vector<size_t>& shape, const int32_t* data,
             bool compress = false);
  void write(const std::string& name, const std::vector<size_t>& shape, const int64_t* data,
             bool compress = false);
  // A 1-D dataset of fixed-length strings, each as long as the longest (at least 1), nul-padded.
  void write_strings(const std::string& name, const std::vector<std::string>& values);
  // Reads such a list back (trailing nuls dropped); variable-length strings are an Error.
  std::vector<std::string> read_strings(const std::string& dataset) const;

  // ---- scalar attributes of this group ----
  bool has_attribute(const std::string& key) const;
  // A fixed-length string as long as the value (an empty value is one nul).
  void set_attribute(const std::string& key, const std::string& value);
  void set_attribute(const std::string& key, double value);   // float64
  void set_attribute(const std::string& key, int32_t value);  // int32
  // A missing attribute is "<file>: <name>: attribute '<key>' missing".
  std::string string_attribute(const std::string& key) const;
  double double_attribute(const std::string& key) const;
  // Every string attribute (others are skipped), by key.
  std::map<std::string, std::string> string_attributes() const;

 private:
  [[noreturn]] void fail(const std::string& object, const std::string& why) const;
  std::shared_ptr<State> state_;
};

// Whether `path` is a readable file holding the HDF5 signature where the format puts it (byte
// 0, or 512, 1024, 2048, ... after a user block). No error for a missing file: false.
bool is_hdf5_file(const std::string& path);

// The root group of `path`, opened read-only. A missing, empty or non-HDF5 file, or one HDF5
// cannot open (truncated), is a pb4u::Error naming `path`.
Hdf5Group open_hdf5(const std::string& path);

// Writes `path` atomically: `fill` gets the root group of a new file at a temporary path, which
// replaces `path` once `fill` returns and the file is closed. Any error (fill's own included)
// removes the temporary and leaves `path` untouched; HDF5 errors name `path`. `fill` must not
// keep copies of the groups it gets.
void write_hdf5(const std::string& path, const std::function<void(Hdf5Group& root)>& fill);

}  // namespace pb4u

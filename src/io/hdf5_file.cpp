#include "pb4u/io/hdf5_file.h"

#include <H5Cpp.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "pb4u/util/atomic_file.h"
#include "pb4u/util/error.h"

namespace pb4u {

struct Hdf5Group::State {
  std::shared_ptr<H5::H5File> file;  // keeps the file open while a group of it lives
  H5::Group group;
  std::string path;  // the file as errors name it
  std::string name;  // the group's path in the file
};

namespace {

std::string hdf5_reason(const H5::Exception& e) {
  const std::string detail = e.getDetailMsg();
  return detail.empty() ? e.getFuncName() : detail;
}

// Runs f, turning an HDF5 exception into "<file>: <object>: cannot <doing>: <reason>".
template <class F>
auto hdf5_guard(const Hdf5Group::State& s, const std::string& object, const std::string& doing, F&& f) {
  try {
    return f();
  } catch (const H5::Exception& e) {
    fail_file(s.path, object + ": cannot " + doing + ": " + hdf5_reason(e));
  }
}

const H5::PredType& hdf5_memory_type(const double*) { return H5::PredType::NATIVE_DOUBLE; }
const H5::PredType& hdf5_memory_type(const float*) { return H5::PredType::NATIVE_FLOAT; }
const H5::PredType& hdf5_memory_type(const int32_t*) { return H5::PredType::NATIVE_INT32; }
const H5::PredType& hdf5_memory_type(const int64_t*) { return H5::PredType::NATIVE_INT64; }

std::shared_ptr<Hdf5Group::State> hdf5_root(std::shared_ptr<H5::H5File> file, const std::string& path) {
  H5::Group root = file->openGroup("/");
  return std::make_shared<Hdf5Group::State>(Hdf5Group::State{std::move(file), root, path, "/"});
}

}  // namespace

Hdf5Group::Hdf5Group(std::shared_ptr<State> state) : state_(std::move(state)) {}

const std::string& Hdf5Group::file() const { return state_->path; }
const std::string& Hdf5Group::name() const { return state_->name; }

std::string Hdf5Group::child_path(const std::string& child) const {
  return (state_->name == "/" ? "" : state_->name) + "/" + child;
}

void Hdf5Group::fail(const std::string& object, const std::string& why) const {
  fail_file(state_->path, object + ": " + why);
}

// ---- children ----

bool Hdf5Group::has(const std::string& child) const {
  return hdf5_guard(*state_, child_path(child), "look up", [&] { return state_->group.nameExists(child); });
}

std::vector<std::string> Hdf5Group::children() const {
  return hdf5_guard(*state_, state_->name, "list", [&] {
    std::vector<std::string> out;
    for (hsize_t i = 0; i < state_->group.getNumObjs(); ++i) out.push_back(state_->group.getObjnameByIdx(i));
    return out;
  });
}

Hdf5Group Hdf5Group::group(const std::string& child) const {
  if (!has(child)) fail(child_path(child), "missing");
  H5::Group g = hdf5_guard(*state_, child_path(child), "open the group",
                           [&] { return state_->group.openGroup(child); });
  return Hdf5Group(std::make_shared<State>(State{state_->file, g, state_->path, child_path(child)}));
}

Hdf5Group Hdf5Group::create_group(const std::string& child) {
  H5::Group g = hdf5_guard(*state_, child_path(child), "create the group",
                           [&] { return state_->group.createGroup(child); });
  return Hdf5Group(std::make_shared<State>(State{state_->file, g, state_->path, child_path(child)}));
}

// ---- datasets ----

namespace {

H5::DataSet hdf5_open_dataset(const Hdf5Group& g, const Hdf5Group::State& s, const std::string& name) {
  if (!g.has(name)) fail_file(s.path, g.child_path(name) + ": missing");
  return hdf5_guard(s, g.child_path(name), "open the dataset", [&] { return s.group.openDataSet(name); });
}

template <class T>
void hdf5_read(const Hdf5Group& g, const Hdf5Group::State& s, const std::string& name, T* out) {
  H5::DataSet ds = hdf5_open_dataset(g, s, name);
  hdf5_guard(s, g.child_path(name), "read", [&] {
    if (ds.getSpace().getSimpleExtentNpoints() > 0) ds.read(out, hdf5_memory_type(out));
  });
}

template <class T>
void hdf5_write(const Hdf5Group::State& s, const std::string& object, const std::string& name,
                const std::vector<size_t>& shape, const T* data, bool compress) {
  hdf5_guard(s, object, "write", [&] {
    std::vector<hsize_t> dims(shape.begin(), shape.end());
    H5::DataSpace space(static_cast<int>(dims.size()), dims.data());
    H5::DSetCreatPropList props;
    hsize_t total = 1;
    for (hsize_t d : dims) total *= d;
    if (compress && total >= 4096) {  // chunk along the first axis
      std::vector<hsize_t> chunk = dims;
      chunk[0] = std::max<hsize_t>(
          1, std::min<hsize_t>(dims[0], (hsize_t(1) << 16) / std::max<hsize_t>(1, total / dims[0])));
      props.setChunk(static_cast<int>(chunk.size()), chunk.data());
      props.setDeflate(4);
    }
    H5::DataSet ds = s.group.createDataSet(name, hdf5_memory_type(data), space, props);
    if (total > 0) ds.write(data, hdf5_memory_type(data));
  });
}

}  // namespace

std::vector<size_t> Hdf5Group::shape(const std::string& dataset) const {
  H5::DataSet ds = hdf5_open_dataset(*this, *state_, dataset);
  return hdf5_guard(*state_, child_path(dataset), "read the shape", [&] {
    H5::DataSpace space = ds.getSpace();
    std::vector<hsize_t> dims(space.getSimpleExtentNdims());
    space.getSimpleExtentDims(dims.data());
    return std::vector<size_t>(dims.begin(), dims.end());
  });
}

void Hdf5Group::read(const std::string& dataset, double* out) const {
  hdf5_read(*this, *state_, dataset, out);
}
void Hdf5Group::read(const std::string& dataset, float* out) const {
  hdf5_read(*this, *state_, dataset, out);
}
void Hdf5Group::read(const std::string& dataset, int32_t* out) const {
  hdf5_read(*this, *state_, dataset, out);
}
void Hdf5Group::read(const std::string& dataset, int64_t* out) const {
  hdf5_read(*this, *state_, dataset, out);
}

void Hdf5Group::write(const std::string& name, const std::vector<size_t>& shape, const double* data,
                      bool compress) {
  hdf5_write(*state_, child_path(name), name, shape, data, compress);
}
void Hdf5Group::write(const std::string& name, const std::vector<size_t>& shape, const float* data,
                      bool compress) {
  hdf5_write(*state_, child_path(name), name, shape, data, compress);
}
void Hdf5Group::write(const std::string& name, const std::vector<size_t>& shape, const int32_t* data,
                      bool compress) {
  hdf5_write(*state_, child_path(name), name, shape, data, compress);
}
void Hdf5Group::write(const std::string& name, const std::vector<size_t>& shape, const int64_t* data,
                      bool compress) {
  hdf5_write(*state_, child_path(name), name, shape, data, compress);
}

void Hdf5Group::write_strings(const std::string& name, const std::vector<std::string>& values) {
  size_t len = 1;
  for (const auto& x : values) len = std::max(len, x.size());
  std::vector<char> buf(std::max<size_t>(1, values.size()) * len, '\0');
  for (size_t i = 0; i < values.size(); ++i)
    std::copy(values[i].begin(), values[i].end(), buf.begin() + i * len);
  hdf5_guard(*state_, child_path(name), "write", [&] {
    H5::StrType type(H5::PredType::C_S1, len);
    hsize_t dims[1] = {values.size()};
    H5::DataSet ds = state_->group.createDataSet(name, type, H5::DataSpace(1, dims));
    if (!values.empty()) ds.write(buf.data(), type);
  });
}

std::vector<std::string> Hdf5Group::read_strings(const std::string& dataset) const {
  const std::vector<size_t> d = shape(dataset);
  if (d.size() != 1) fail(child_path(dataset), "expected a list of strings");
  H5::DataSet ds = hdf5_open_dataset(*this, *state_, dataset);
  return hdf5_guard(*state_, child_path(dataset), "read", [&] {
    H5::StrType type = ds.getStrType();
    if (type.isVariableStr()) fail(child_path(dataset), "variable-length strings are not supported");
    const size_t len = type.getSize();
    std::vector<char> buf(d[0] * len + 1, '\0');
    if (d[0] > 0) ds.read(buf.data(), type);
    std::vector<std::string> out;
    for (size_t i = 0; i < d[0]; ++i) {
      const char* p = buf.data() + i * len;
      out.emplace_back(p, strnlen(p, len));
    }
    return out;
  });
}

// ---- attributes ----

bool Hdf5Group::has_attribute(const std::string& key) const {
  return hdf5_guard(*state_, state_->name, "look up attribute '" + key + "'",
                    [&] { return state_->group.attrExists(key); });
}

void Hdf5Group::set_attribute(const std::string& key, const std::string& value) {
  hdf5_guard(*state_, state_->name, "write attribute '" + key + "'", [&] {
    H5::StrType type(H5::PredType::C_S1, std::max<size_t>(1, value.size()));
    H5::Attribute a = state_->group.createAttribute(key, type, H5::DataSpace(H5S_SCALAR));
    const std::string padded = value.empty() ? std::string(1, '\0') : value;
    a.write(type, padded.data());
  });
}

void Hdf5Group::set_attribute(const std::string& key, double value) {
  hdf5_guard(*state_, state_->name, "write attribute '" + key + "'", [&] {
    H5::Attribute a =
        state_->group.createAttribute(key, H5::PredType::NATIVE_DOUBLE, H5::DataSpace(H5S_SCALAR));
    a.write(H5::PredType::NATIVE_DOUBLE, &value);
  });
}

void Hdf5Group::set_attribute(const std::string& key, int32_t value) {
  hdf5_guard(*state_, state_->name, "write attribute '" + key + "'", [&] {
    H5::Attribute a =
        state_->group.createAttribute(key, H5::PredType::NATIVE_INT32, H5::DataSpace(H5S_SCALAR));
    a.write(H5::PredType::NATIVE_INT32, &value);
  });
}

std::string Hdf5Group::string_attribute(const std::string& key) const {
  if (!has_attribute(key)) fail(state_->name, "attribute '" + key + "' missing");
  return hdf5_guard(*state_, state_->name, "read attribute '" + key + "'", [&] {
    H5::Attribute a = state_->group.openAttribute(key);
    std::string value;
    a.read(a.getStrType(), value);  // fixed-length: up to the first nul
    return value;
  });
}

double Hdf5Group::double_attribute(const std::string& key) const {
  if (!has_attribute(key)) fail(state_->name, "attribute '" + key + "' missing");
  return hdf5_guard(*state_, state_->name, "read attribute '" + key + "'", [&] {
    double v = 0;
    state_->group.openAttribute(key).read(H5::PredType::NATIVE_DOUBLE, &v);
    return v;
  });
}

std::map<std::string, std::string> Hdf5Group::string_attributes() const {
  return hdf5_guard(*state_, state_->name, "read the attributes", [&] {
    std::map<std::string, std::string> out;
    for (int i = 0; i < state_->group.getNumAttrs(); ++i) {
      H5::Attribute a = state_->group.openAttribute(static_cast<unsigned>(i));
      if (a.getTypeClass() != H5T_STRING) continue;
      std::string value;
      a.read(a.getStrType(), value);
      out[a.getName()] = value;
    }
    return out;
  });
}

// ---- files ----

bool is_hdf5_file(const std::string& path) {
  static const char kSignature[8] = {'\x89', 'H', 'D', 'F', '\r', '\n', '\x1a', '\n'};
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  for (std::streamoff at = 0; at >= 0 && at + 8 <= size; at = at ? 2 * at : 512) {
    char head[8];
    in.seekg(at);
    if (!in.read(head, 8)) return false;
    if (std::memcmp(head, kSignature, 8) == 0) return true;
  }
  return false;
}

Hdf5Group open_hdf5(const std::string& path) {
  H5::Exception::dontPrint();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) fail_file(path, "no such file");
  if (std::filesystem::is_directory(path, ec)) fail_file(path, "is a directory, not a file");
  if (!std::ifstream(path, std::ios::binary)) fail_file(path, "cannot open the file");
  if (std::filesystem::file_size(path, ec) == 0) fail_file(path, "file is empty");
  if (!is_hdf5_file(path)) fail_file(path, "not an HDF5 file");
  try {
    return Hdf5Group(hdf5_root(std::make_shared<H5::H5File>(path, H5F_ACC_RDONLY), path));
  } catch (const H5::Exception& e) {
    fail_file(path, "cannot open HDF5 file (corrupt or truncated?): " + hdf5_reason(e));
  }
}

void write_hdf5(const std::string& path, const std::function<void(Hdf5Group& root)>& fill) {
  H5::Exception::dontPrint();
  const std::string tmp = temp_path_for(path);
  try {
    {
      auto file = std::make_shared<H5::H5File>(tmp, H5F_ACC_TRUNC);
      Hdf5Group root(hdf5_root(file, path));
      fill(root);
      file->flush(H5F_SCOPE_GLOBAL);
    }  // every handle closed: the file is complete
    commit_file(tmp, path);
  } catch (const H5::Exception& e) {
    std::remove(tmp.c_str());
    fail_file(path, "cannot write HDF5: " + hdf5_reason(e));
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
}

}  // namespace pb4u

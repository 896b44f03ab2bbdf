#include "pb4u/io/module_hdf5.h"

#include <H5Cpp.h>

#include <filesystem>
#include <sstream>
#include <vector>

#include "pb4u/util/atomic_file.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace {

H5::PredType h5_type(torch::ScalarType t) {
  switch (t) {
    case torch::kFloat64: return H5::PredType::NATIVE_DOUBLE;
    case torch::kInt64: return H5::PredType::NATIVE_INT64;
    default: return H5::PredType::NATIVE_FLOAT;
  }
}

torch::ScalarType storage_type(torch::ScalarType t) {
  if (t == torch::kFloat64 || t == torch::kInt64) return t;
  if (t == torch::kInt32 || t == torch::kBool || t == torch::kUInt8) return torch::kInt64;
  return torch::kFloat32;
}

std::map<std::string, torch::Tensor> named_tensors(const torch::nn::Module& module) {
  std::map<std::string, torch::Tensor> out;
  for (const auto& p : module.named_parameters()) out[p.key()] = p.value();
  for (const auto& b : module.named_buffers()) out[b.key()] = b.value();
  return out;
}

void open_file(H5::H5File& file, const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) fail_file(path, "no such file");
  if (std::filesystem::file_size(path, ec) == 0) fail_file(path, "file is empty");
  try {
    if (!H5::H5File::isHdf5(path)) fail_file(path, "not an HDF5 file");
    file.openFile(path, H5F_ACC_RDONLY);
  } catch (const H5::Exception& e) {
    fail_file(path, "cannot open HDF5 file: " + e.getDetailMsg());
  }
}

}  // namespace

void save_module_hdf5(const std::string& path, const torch::nn::Module& module,
                      const std::map<std::string, std::string>& attributes) {
  H5::Exception::dontPrint();
  std::string tmp = temp_path_for(path);
  try {
    H5::H5File file(tmp, H5F_ACC_TRUNC);
    H5::Group root = file.openGroup("/");
    for (const auto& [key, value] : attributes) {
      H5::StrType type(H5::PredType::C_S1, std::max<size_t>(value.size(), 1));
      H5::Attribute attr = root.createAttribute(key, type, H5::DataSpace(H5S_SCALAR));
      attr.write(type, value.empty() ? std::string(" ") : value);
    }
    for (const auto& [name, tensor] : named_tensors(module)) {
      torch::Tensor t = tensor.detach().to(torch::kCPU, storage_type(tensor.scalar_type())).contiguous();
      std::vector<hsize_t> dims(t.sizes().begin(), t.sizes().end());
      H5::DataSpace space(static_cast<int>(dims.size()), dims.data());
      H5::DataSet ds = file.createDataSet(name, h5_type(t.scalar_type()), space);
      if (t.numel() > 0) ds.write(t.data_ptr(), h5_type(t.scalar_type()));
    }
    file.close();
  } catch (const H5::Exception& e) {
    std::remove(tmp.c_str());
    fail_file(path, "cannot write HDF5: " + e.getDetailMsg());
  }
  commit_file(tmp, path);
}

std::map<std::string, std::string> read_hdf5_attributes(const std::string& path) {
  H5::Exception::dontPrint();
  H5::H5File file;
  open_file(file, path);
  std::map<std::string, std::string> out;
  try {
    H5::Group root = file.openGroup("/");
    for (int i = 0; i < root.getNumAttrs(); ++i) {
      H5::Attribute attr = root.openAttribute(static_cast<unsigned>(i));
      if (attr.getTypeClass() != H5T_STRING) continue;
      std::string value;
      attr.read(attr.getStrType(), value);
      out[attr.getName()] = value;
    }
  } catch (const H5::Exception& e) {
    fail_file(path, "cannot read attributes: " + e.getDetailMsg());
  }
  return out;
}

void load_module_hdf5(const std::string& path, torch::nn::Module& module) {
  H5::Exception::dontPrint();
  H5::H5File file;
  open_file(file, path);
  // Read everything first, so a bad file leaves the module untouched.
  std::map<std::string, torch::Tensor> loaded;
  auto targets = named_tensors(module);
  for (const auto& [name, target] : targets) {
    if (!file.nameExists(name)) fail_file(path, "does not match the model: no tensor '" + name + "'");
    try {
      H5::DataSet ds = file.openDataSet(name);
      H5::DataSpace space = ds.getSpace();
      std::vector<hsize_t> dims(space.getSimpleExtentNdims());
      space.getSimpleExtentDims(dims.data());
      std::vector<int64_t> shape(dims.begin(), dims.end());
      if (c10::IntArrayRef(shape) != target.sizes()) {
        std::ostringstream why;
        why << "does not match the model: '" << name << "' has shape " << c10::IntArrayRef(shape)
            << ", the model expects " << target.sizes();
        fail_file(path, why.str());
      }
      torch::Tensor t = torch::empty(shape, torch::TensorOptions().dtype(storage_type(target.scalar_type())));
      if (t.numel() > 0) ds.read(t.data_ptr(), h5_type(t.scalar_type()));
      loaded[name] = t;
    } catch (const H5::Exception& e) {
      fail_file(path, "cannot read '" + name + "': " + e.getDetailMsg());
    }
  }
  torch::NoGradGuard no_grad;
  for (auto& [name, target] : targets) target.copy_(loaded[name].to(target.options()));
}

}  // namespace pb4u

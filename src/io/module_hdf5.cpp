#include "pb4u/io/module_hdf5.h"

#include <sstream>
#include <vector>

#include "pb4u/io/hdf5_file.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace {

// The type a tensor is stored as: float64 and int64 as they are, other integers as int64,
// everything else as float32.
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

}  // namespace

void save_module_hdf5(const std::string& path, const torch::nn::Module& module,
                      const std::map<std::string, std::string>& attributes) {
  write_hdf5(path, [&](Hdf5Group& root) {
    for (const auto& [key, value] : attributes) root.set_attribute(key, value);
    for (const auto& [name, tensor] : named_tensors(module)) {
      torch::Tensor t = tensor.detach().to(torch::kCPU, storage_type(tensor.scalar_type())).contiguous();
      const std::vector<size_t> shape(t.sizes().begin(), t.sizes().end());
      if (t.scalar_type() == torch::kFloat64) root.write(name, shape, t.data_ptr<double>());
      else if (t.scalar_type() == torch::kInt64) root.write(name, shape, t.data_ptr<int64_t>());
      else root.write(name, shape, t.data_ptr<float>());
    }
  });
}

std::map<std::string, std::string> read_hdf5_attributes(const std::string& path) {
  return open_hdf5(path).string_attributes();
}

void load_module_hdf5(const std::string& path, torch::nn::Module& module) {
  const Hdf5Group root = open_hdf5(path);
  // Read everything first, so a bad file leaves the module untouched.
  std::map<std::string, torch::Tensor> loaded;
  auto targets = named_tensors(module);
  for (const auto& [name, target] : targets) {
    if (!root.has(name)) fail_file(path, "does not match the model: no tensor '" + name + "'");
    const std::vector<size_t> dims = root.shape(name);
    const std::vector<int64_t> shape(dims.begin(), dims.end());
    if (c10::IntArrayRef(shape) != target.sizes()) {
      std::ostringstream why;
      why << "does not match the model: '" << name << "' has shape " << c10::IntArrayRef(shape)
          << ", the model expects " << target.sizes();
      fail_file(path, why.str());
    }
    torch::Tensor t = torch::empty(shape, torch::TensorOptions().dtype(storage_type(target.scalar_type())));
    if (t.scalar_type() == torch::kFloat64) root.read(name, t.data_ptr<double>());
    else if (t.scalar_type() == torch::kInt64) root.read(name, t.data_ptr<int64_t>());
    else root.read(name, t.data_ptr<float>());
    loaded[name] = t;
  }
  torch::NoGradGuard no_grad;
  for (auto& [name, target] : targets) target.copy_(loaded[name].to(target.options()));
}

}  // namespace pb4u

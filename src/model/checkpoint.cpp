#include "pb4u/model/checkpoint.h"

#include <ATen/CPUGeneratorImpl.h>

#include <algorithm>
#include <cstring>
#include <mutex>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <sstream>

#include "pb4u/util/atomic_file.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace fs = std::filesystem;

namespace {

torch::Tensor cpu_generator_state() {
  at::Generator gen = at::detail::getDefaultCPUGenerator();
  std::lock_guard<std::mutex> lock(gen.mutex());
  return gen.get_state();
}

torch::Tensor bytes_to_tensor(const std::string& s) {
  auto t = torch::empty({static_cast<int64_t>(s.size())}, torch::kUInt8);
  if (!s.empty()) std::memcpy(t.data_ptr(), s.data(), s.size());
  return t;
}

std::string tensor_to_bytes(const torch::Tensor& t) {
  auto c = t.contiguous().to(torch::kCPU, torch::kUInt8);
  return std::string(reinterpret_cast<const char*>(c.data_ptr()), static_cast<size_t>(c.numel()));
}

void write_meta(torch::serialize::OutputArchive& ar, const CheckpointMeta& meta) {
  ar.write("meta/kind", bytes_to_tensor(meta.kind));
  ar.write("meta/format_version", torch::tensor(meta.format_version, torch::kInt64));
  ar.write("meta/step", torch::tensor(meta.step, torch::kInt64));
  ar.write("meta/config_yaml", bytes_to_tensor(meta.config_yaml));
  ar.write("meta/host_rng_state", bytes_to_tensor(meta.host_rng_state));
  ar.write("meta/elapsed_seconds", torch::tensor(meta.elapsed_seconds, torch::kFloat64));
  ar.write("meta/skipped_steps", torch::tensor(meta.skipped_steps, torch::kInt64));
  ar.write("meta/torch_rng_state", cpu_generator_state());
}

torch::Tensor read_tensor(torch::serialize::InputArchive& ar, const std::string& key,
                          const std::string& path) {
  torch::Tensor t;
  if (!ar.try_read(key, t)) fail_file(path, "not a pb4u checkpoint (no '" + key + "')");
  return t;
}

CheckpointMeta read_meta(torch::serialize::InputArchive& ar, const std::string& path) {
  CheckpointMeta meta;
  meta.kind = tensor_to_bytes(read_tensor(ar, "meta/kind", path));
  if (meta.kind != "pb4u-train-checkpoint")
    fail_file(path, "not a pb4u training checkpoint (kind '" + meta.kind + "')");
  meta.format_version = read_tensor(ar, "meta/format_version", path).item<int64_t>();
  if (meta.format_version != 1)
    fail_file(path, "checkpoint format " + std::to_string(meta.format_version) +
                        " is not supported (expected 1)");
  meta.step = read_tensor(ar, "meta/step", path).item<int64_t>();
  meta.config_yaml = tensor_to_bytes(read_tensor(ar, "meta/config_yaml", path));
  meta.host_rng_state = tensor_to_bytes(read_tensor(ar, "meta/host_rng_state", path));
  meta.elapsed_seconds = read_tensor(ar, "meta/elapsed_seconds", path).item<double>();
  meta.skipped_steps = read_tensor(ar, "meta/skipped_steps", path).item<int64_t>();
  return meta;
}

// Every tensor is read onto `device`: as saved, a CUDA run's checkpoint would name its GPU, and
// could not be read on a machine without it (or would move a model to where it was trained).
void open_archive(torch::serialize::InputArchive& ar, const std::string& path, torch::Device device) {
  std::error_code ec;
  if (!fs::exists(path, ec)) fail_file(path, "no such checkpoint");
  if (fs::is_directory(path, ec)) fail_file(path, "is a directory, not a checkpoint");
  if (fs::file_size(path, ec) == 0) fail_file(path, "checkpoint is empty");
  try {
    ar.load_from(path, device);
  } catch (const c10::Error& e) {
    fail_file(path, "corrupt or truncated checkpoint (" +
                        std::string(e.what_without_backtrace()).substr(0, 160) + ")");
  } catch (const std::exception& e) {
    // TorchScript's importer reports a damaged archive with std::runtime_error (found by
    // checkpoint_fuzz), not c10::Error.
    fail_file(path, "corrupt or truncated checkpoint (" + std::string(e.what()).substr(0, 160) + ")");
  }
}

// torch's Module::load silently replaces a tensor of another shape; check every parameter and
// buffer first so a mismatched checkpoint is an error, not a different model.
void check_shapes(const torch::nn::Module& module, torch::serialize::InputArchive& ar,
                  const std::string& prefix, const std::string& path) {
  auto check = [&](const std::string& name, const torch::Tensor& expected) {
    torch::Tensor stored;
    if (!ar.try_read(name, stored))
      fail_file(path, "checkpoint does not match the model: no '" + prefix + name + "'");
    if (stored.sizes() != expected.sizes()) {
      std::ostringstream why;
      why << "checkpoint does not match the model: '" << prefix << name << "' has shape "
          << stored.sizes() << ", the model expects " << expected.sizes();
      fail_file(path, why.str());
    }
  };
  for (const auto& p : module.named_parameters(/*recurse=*/false)) check(p.key(), p.value());
  for (const auto& b : module.named_buffers(/*recurse=*/false)) check(b.key(), b.value());
  for (const auto& child : module.named_children()) {
    torch::serialize::InputArchive child_ar;
    if (!ar.try_read(child.key(), child_ar))
      fail_file(path, "checkpoint does not match the model: no module '" + prefix + child.key() + "'");
    check_shapes(*child.value(), child_ar, prefix + child.key() + ".", path);
  }
}

}  // namespace

void save_checkpoint(const std::string& path, const torch::nn::Module& model,
                     const torch::optim::Optimizer* optimizer, const CheckpointMeta& meta) {
  torch::serialize::OutputArchive ar;
  write_meta(ar, meta);
  torch::serialize::OutputArchive model_ar;
  model.save(model_ar);
  ar.write("model", model_ar);
  if (optimizer) {
    torch::serialize::OutputArchive opt_ar;
    optimizer->save(opt_ar);
    ar.write("optimizer", opt_ar);
  }
  std::string tmp = temp_path_for(path);
  try {
    ar.save_to(tmp);
  } catch (const c10::Error& e) {
    std::remove(tmp.c_str());
    fail_file(path, std::string("cannot write checkpoint: ") + e.what_without_backtrace());
  }
  commit_file(tmp, path);
}

CheckpointMeta read_checkpoint_meta(const std::string& path) {
  torch::serialize::InputArchive ar;
  open_archive(ar, path, torch::kCPU);
  return read_meta(ar, path);
}

CheckpointMeta load_checkpoint(const std::string& path, torch::nn::Module& model,
                               torch::optim::Optimizer* optimizer, torch::Device device) {
  torch::serialize::InputArchive ar;
  open_archive(ar, path, device);
  CheckpointMeta meta = read_meta(ar, path);
  torch::serialize::InputArchive model_ar;
  if (!ar.try_read("model", model_ar)) fail_file(path, "checkpoint has no model");
  check_shapes(model, model_ar, "", path);
  try {
    model.load(model_ar);
  } catch (const c10::Error& e) {
    std::string why = e.what_without_backtrace();
    fail_file(path, "checkpoint does not match the model: " + why.substr(0, why.find('\n')));
  }
  if (optimizer) {
    torch::serialize::InputArchive opt_ar;
    if (!ar.try_read("optimizer", opt_ar)) fail_file(path, "checkpoint has no optimiser state");
    try {
      optimizer->load(opt_ar);
    } catch (const c10::Error& e) {
      fail_file(path, "optimiser state does not match");
    }
  }
  torch::Tensor rng;
  if (ar.try_read("meta/torch_rng_state", rng)) {
    at::Generator gen = at::detail::getDefaultCPUGenerator();
    std::lock_guard<std::mutex> lock(gen.mutex());
    gen.set_state(rng.to(torch::kCPU));
  }
  return meta;
}

std::string checkpoint_path(const std::string& dir, int64_t step) {
  char name[32];
  std::snprintf(name, sizeof name, "step_%08lld.pt", static_cast<long long>(step));
  return (fs::path(dir) / name).string();
}

std::vector<std::string> list_checkpoints(const std::string& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return out;
  static const std::regex pattern("step_[0-9]{8}\\.pt");
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.is_regular_file() && std::regex_match(e.path().filename().string(), pattern))
      out.push_back(e.path().string());
  std::sort(out.begin(), out.end());  // zero-padded: lexical order is step order
  return out;
}

std::string latest_checkpoint(const std::string& dir) {
  auto all = list_checkpoints(dir);
  return all.empty() ? "" : all.back();
}

void prune_checkpoints(const std::string& dir, int keep) {
  auto all = list_checkpoints(dir);
  for (size_t i = 0; i + keep < all.size(); ++i) fs::remove(all[i]);
}

}  // namespace pb4u

#include "pb4u/util/device.h"

#include <torch/cuda.h>

#include "pb4u/util/error.h"

namespace pb4u {

torch::Device resolve_device(const std::string& name, const std::string& key) {
  if (name == "cpu") return torch::kCPU;
  const bool cuda = name == "cuda" || name.rfind("cuda:", 0) == 0;
  if (!cuda) throw Error(key + ": expected cpu, cuda or cuda:N, got '" + name + "'");
  // The name's form first, so a malformed one ("cuda:", "cuda:x") reads the same with or without a GPU.
  int index = 0;
  if (name != "cuda") {
    const std::string digits = name.substr(5);
    if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos || digits.size() > 3)
      throw Error(key + ": expected cpu, cuda or cuda:N, got '" + name + "'");
    index = std::stoi(digits);
  }
  if (!torch::cuda::is_available())
    throw Error(key + ": cuda requested but this build of libtorch or this machine has no CUDA device "
                      "(build against a CUDA libtorch: docs/cuda.md)");
  if (index >= static_cast<int>(torch::cuda::device_count()))
    throw Error(key + ": " + name + " requested but there are " + std::to_string(torch::cuda::device_count()) +
                " CUDA devices");
  return torch::Device(torch::kCUDA, static_cast<c10::DeviceIndex>(index));
}

}  // namespace pb4u

#pragma once
// The compute device named in a config (`run.device`) or on the command line (`--device`).
#include <torch/types.h>

#include <string>

namespace pb4u {

// "cpu" -> CPU; "cuda" or "cuda:N" -> that GPU. Throws pb4u::Error naming `key` for any other
// name, or for cuda when this build of libtorch or this machine has no CUDA device.
torch::Device resolve_device(const std::string& name, const std::string& key);

}  // namespace pb4u

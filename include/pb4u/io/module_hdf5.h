#pragma once
// Portable model files: every parameter and buffer of a torch::nn::Module as one HDF5 dataset
// (float32/float64/int64, named by its dotted path, e.g. "blocks.3.edge_mlp.0.weight"), plus
// string attributes on the root group (format, version, config...). Readable by any HDF5 tool
// (h5ls, h5py) without pb4u or PyTorch.
#include <torch/torch.h>

#include <map>
#include <string>

namespace pb4u {

// Writes atomically. `attributes` become root-group string attributes.
void save_module_hdf5(const std::string& path, const torch::nn::Module& module,
                      const std::map<std::string, std::string>& attributes);

// Root-group string attributes only. Throws pb4u::Error naming `path` when it is missing or not HDF5.
std::map<std::string, std::string> read_hdf5_attributes(const std::string& path);

// Copies every parameter and buffer of `module` from the file. A missing dataset or a shape
// mismatch is a pb4u::Error naming the file and the tensor; the module is untouched then.
void load_module_hdf5(const std::string& path, torch::nn::Module& module);

}  // namespace pb4u

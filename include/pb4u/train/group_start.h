#pragma once
// How the ranks of a data-parallel run start as one (issue 10): rank 0 owns the run directory
// and decides; the others learn its verdict, check that every rank runs the same config and
// agrees on --resume, and take rank 0's checkpoint and weights.
#include <torch/torch.h>

#include <functional>
#include <string>

#include "pb4u/train/distributed.h"

namespace pb4u {

// Every rank learns rank 0's `problem` (empty: rank 0 could start) and checks that all ranks
// hold rank 0's config_yaml and the same `resume`. Throws pb4u::Error on every rank otherwise,
// naming what differs.
void agree_to_start(DistributedGroup& group, const std::string& problem, const std::string& config_yaml,
                    bool resume);

// Rank 0's checkpoint file (its bytes in `root_bytes`; ignored elsewhere) reaches every rank:
// each other rank writes it to a temporary file, calls load(path) and removes the file.
void share_checkpoint(DistributedGroup& group, const std::string& root_bytes,
                      const std::function<void(const std::string& path)>& load);

// Rank 0's parameters and buffers on every rank, whatever each rank's initialisation did.
void broadcast_module_state(DistributedGroup& group, torch::nn::Module& module);

// The bytes of a file (a checkpoint to send); pb4u::Error naming it if it cannot be read.
std::string read_binary_file(const std::string& path);

}  // namespace pb4u

// Fuzzes checkpoint loading into a small module (meta, shape checks, optimiser state).
#include <torch/torch.h>

#include <cstdlib>

#include "fuzz_input.h"
#include "pb4u/model/checkpoint.h"
#include "pb4u/util/error.h"

// With PB4U_FUZZ_SEED_DIR set, writes a valid checkpoint there as the seed corpus.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = std::getenv("PB4U_FUZZ_SEED_DIR")) {
    torch::nn::Linear net(3, 4);
    pb4u::CheckpointMeta meta;
    meta.step = 3;
    meta.config_yaml = "a: 1\n";
    pb4u::save_checkpoint(std::string(dir) + "/valid.pt", *net, nullptr, meta);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static torch::nn::Linear net(3, 4);
  std::string path = pb4u::fuzz::write_input(data, size, ".pt");
  try {
    pb4u::read_checkpoint_meta(path);
    torch::optim::Adam opt(net->parameters());
    pb4u::load_checkpoint(path, *net, &opt);
  } catch (const pb4u::Error&) {
  }
  std::remove(path.c_str());
  return 0;
}

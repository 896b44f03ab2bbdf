#pragma once
// run.init_from: a new training run starts from the weights and normaliser statistics of
// another model, given as a training checkpoint (<run>/final.pt, checkpoints/step_*.pt) or as
// a portable export (`pb4u export`, e.g. data/pretrained/pb4u.h5). An export is what survives
// when a run directory does not, so a shipped model can be fine-tuned. Step, optimiser and
// schedule are not taken: the run starts afresh from step 0.
#include <torch/torch.h>

#include <cstdint>
#include <string>

namespace pb4u {

// Copies every parameter and buffer of the model in `path` into `model` (on `device`) and
// returns the step the weights were trained to. The model config may differ where shapes do
// not (an export's inference switches are not taken). Throws a one-line pb4u::Error naming
// `path` and the tensor when the file is missing or corrupt, or a parameter or buffer is
// missing or of another shape.
int64_t init_weights_from(const std::string& path, torch::nn::Module& model, torch::Device device);

}  // namespace pb4u

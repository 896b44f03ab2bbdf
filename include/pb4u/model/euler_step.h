#pragma once
// Forward Euler with pins (SPEC 4): v_{t+1} = v_t + a dt, x_{t+1} = x_t + v_{t+1} dt; pinned
// vertices move to their targets instead. Differentiable in a (training) and x.
#include <torch/torch.h>

#include "pb4u/scene/frame_state.h"

namespace pb4u {

// acceleration (n, 3) m/s^2 -> x_{t+1} (n, 3) m, in the dtype of state.x (float64 states keep
// their precision far from the origin).
torch::Tensor euler_step(const FrameState& state, const torch::Tensor& acceleration);

}  // namespace pb4u

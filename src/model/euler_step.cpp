#include "pb4u/model/euler_step.h"

#include "pb4u/util/error.h"

namespace pb4u {

torch::Tensor euler_step(const FrameState& state, const torch::Tensor& acceleration) {
  const auto& x = state.x;
  auto a = acceleration.to(x.scalar_type());
  auto v_next = (x - state.x_prev) / state.dt + a * state.dt;
  auto x_next = x + v_next * state.dt;
  if (!state.effects.pins || !state.pinned.defined()) return x_next;
  if (!state.pin_targets.defined() || state.pin_targets.sizes() != x.sizes())
    throw Error("frame state: pin_targets must be a (" + std::to_string(x.size(0)) +
                ", 3) tensor when vertices are pinned");
  auto pinned = state.pinned.to(torch::kBool).unsqueeze(1);
  return torch::where(pinned, state.pin_targets.to(x.scalar_type()), x_next);
}

}  // namespace pb4u

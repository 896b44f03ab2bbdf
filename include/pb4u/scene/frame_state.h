#pragma once
// One simulation step's inputs, shared by the graph builder (network features), the physics
// terms (losses / metrics) and the reference solver. Plain tensors, any dtype and device.
#include <torch/torch.h>

#include "pb4u/scene/material.h"
#include "pb4u/scene/effects.h"

namespace pb4u {

// The body at the current and the next frame. Undefined tensors when the scene has no body.
struct BodyFrame {
  torch::Tensor vertices;       // (nb, 3) m, at time t
  torch::Tensor next_vertices;  // (nb, 3) m, at time t + dt (the pose x_{t+1} must respect)
  torch::Tensor faces;          // (mb, 3) int64, outward-oriented
  bool defined() const { return vertices.defined() && vertices.numel() > 0; }
};

// Garment state at time t. The step predicts x_{t+1}.
struct FrameState {
  torch::Tensor x;       // (n, 3) m, positions at t
  torch::Tensor x_prev;  // (n, 3) m, positions at t - dt; v_t = (x - x_prev) / dt
  BodyFrame body;        // undefined unless effects.needs_body()
  torch::Tensor pinned;       // (n) bool; undefined or all false without pins
  torch::Tensor pin_targets;  // (n, 3) m, positions at t + dt for pinned vertices
  Effects effects;
  Material material;
  double dt = 1.0 / 30.0;                   // s
  double gravity[3] = {0.0, -9.81, 0.0};    // m/s^2, y up

  torch::Tensor velocity() const { return (x - x_prev) / dt; }
};

}  // namespace pb4u

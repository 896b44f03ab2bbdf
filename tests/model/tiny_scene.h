#pragma once
// A tiny garment-on-body scene shared by the graph and model tests: a 5 x 5 vertex cloth square
// 1 cm above a 5 x 5 vertex body square (spacing 5 cm vs 7.5 cm), so some garment vertices
// have world edges within 3 cm and some do not.
#include <torch/torch.h>

#include "pb4u/graph/build_graph.h"
#include "pb4u/graph/garment_topology.h"
#include "pb4u/model/pb4u_net.h"
#include "pb4u/model/model_config.h"
#include "pb4u/scene/frame_state.h"
#include "test_util.h"

namespace pb4u::test {

inline torch::Tensor to_tensor(const Eigen::MatrixXd& V) {
  auto t = torch::empty({V.rows(), 3}, torch::kFloat64);
  for (int i = 0; i < V.rows(); ++i)
    for (int k = 0; k < 3; ++k) t[i][k] = V(i, k);
  return t;
}

inline torch::Tensor faces_tensor(const Eigen::MatrixXi& F) {
  auto t = torch::empty({F.rows(), 3}, torch::kInt64);
  for (int i = 0; i < F.rows(); ++i)
    for (int k = 0; k < 3; ++k) t[i][k] = F(i, k);
  return t;
}

struct TinyScene {
  TriMesh rest;
  FrameState state;
};

// Garment moving with a random velocity field, the body drifting; optional pins on row 0.
inline TinyScene tiny_scene(unsigned seed = 0, bool pins = false) {
  torch::manual_seed(seed);
  TinyScene s;
  s.rest = grid_mesh(4, 0.2);
  s.rest.V.rowwise() += Eigen::RowVector3d(0.0, 0.01, 0.0);
  TriMesh body = grid_mesh(4, 0.3);
  body.V.rowwise() += Eigen::RowVector3d(-0.05, 0.0, -0.05);
  auto x = to_tensor(s.rest.V) + 0.003 * torch::randn({s.rest.num_vertices(), 3}, torch::kFloat64);
  s.state.x = x;
  s.state.x_prev = x - 0.02 * torch::randn_like(x);
  s.state.body.vertices = to_tensor(body.V);
  s.state.body.next_vertices = s.state.body.vertices + torch::tensor({0.0, 0.004, 0.001}, torch::kFloat64);
  s.state.body.faces = faces_tensor(body.F);
  if (pins) {
    s.state.effects.pins = true;
    s.state.pinned = torch::zeros({s.rest.num_vertices()}, torch::kBool);
    s.state.pinned.narrow(0, 0, 5).fill_(true);
    s.state.pin_targets = x + 0.01;
  }
  return s;
}

// Width 16, 2 blocks, K_base 3: the test-size model.
inline ModelConfig tiny_config(const std::string& kind = "pb4u") {
  ModelConfig c;
  c.kind = kind;
  c.latent = 16;
  c.num_blocks = 2;
  c.hood_schedule = "f,c0|c1";  // hood: one fine block, one on coarse level 1 alone
  c.k_base = 3;
  c.normalizer_warmup = 5;
  return c;
}

// A calibrated model whose normalisers saw a few frames (so they are not the identity).
inline Pb4uNet warmed_model(const ModelConfig& c, unsigned seed = 0) {
  torch::manual_seed(seed);
  Pb4uNet model(c);
  model->calibrate(0.04);
  model->train();
  for (unsigned i = 0; i < 3; ++i) {
    auto s = tiny_scene(100 + i, true);
    GarmentTopology t = build_garment_topology(s.rest, "garment", c.graph_options().geodesic_anchors);
    model->forward(build_graph(s.state, t, c.graph_options()), 2);
  }
  model->eval();
  return model;
}

}  // namespace pb4u::test

// Graph topology, features, world edges and normalisers against closed forms and invariances.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "model/tiny_scene.h"
#include "pb4u/graph/build_graph.h"
#include "pb4u/graph/features.h"
#include "pb4u/graph/online_normalizer.h"
#include "pb4u/graph/world_edges.h"
#include "pb4u/mesh/geometry.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace {

using test::tiny_scene;

TEST(GarmentTopology, DirectedEdgesAndRestGeometryOfAGrid) {
  TriMesh m = test::grid_mesh(2, 1.0);
  GarmentTopology t = build_garment_topology(m);
  // A 2x2-cell grid: 12 axis edges + 4 diagonals, each in both directions.
  ASSERT_EQ(t.num_mesh_edges(), 32);
  std::set<std::pair<int64_t, int64_t>> directed;
  for (int64_t e = 0; e < 32; ++e) directed.insert({t.senders[e].item<int64_t>(), t.receivers[e].item<int64_t>()});
  for (auto [s, r] : directed) EXPECT_TRUE(directed.count({r, s}));
  EXPECT_EQ(directed.size(), 32u);
  EXPECT_NEAR(t.vertex_area.sum().item<double>(), 1.0, 1e-6);
  EXPECT_NEAR(t.mean_edge_length, mean_edge_length(m.V, m.F), 1e-12);
  auto d = test::to_tensor(m.V).to(torch::kFloat32);
  auto diff = d.index_select(0, t.receivers) - d.index_select(0, t.senders);
  EXPECT_TRUE(torch::allclose(diff, t.rest_direction * t.rest_length.unsqueeze(1), 1e-5, 1e-6));
}

TEST(GarmentTopology, RejectsBadMeshesNamingTheSource) {
  TriMesh m = test::grid_mesh(1, 1.0);
  m.V.row(1) = m.V.row(0);  // a zero-length edge
  try {
    build_garment_topology(m, "shirt.obj");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("shirt.obj"), std::string::npos);
  }
  TriMesh empty;
  empty.V = Eigen::MatrixXd::Zero(3, 3);
  empty.F.resize(0, 3);
  EXPECT_THROW(build_garment_topology(empty), Error);
}

TEST(Features, VertexNormalsOfAFlatGridPointUp) {
  TriMesh m = test::grid_mesh(3, 1.0);
  auto n = vertex_normals(test::to_tensor(m.V), test::faces_tensor(m.F));
  auto up = torch::tensor({0.0, 1.0, 0.0}, torch::kFloat64).expand_as(n);
  EXPECT_TRUE(torch::allclose(n, up, 1e-12, 1e-12));
}

TEST(Features, MeshEdgeFeaturesAreRelativeOnly) {
  auto s = tiny_scene(1);
  GarmentTopology t = build_garment_topology(s.rest);
  auto x = s.state.x.to(torch::kFloat32);
  auto f = mesh_edge_features(x, t);
  ASSERT_EQ(f.size(1), kMeshEdgeFeatureDim);
  // Scaling rest and current shapes by the same factor (and moving them) changes nothing.
  TriMesh scaled = s.rest;
  scaled.V = (2.5 * scaled.V).rowwise() + Eigen::RowVector3d(0.3, -0.2, 0.1);
  GarmentTopology ts = build_garment_topology(scaled);
  auto xs = 2.5 * x + torch::tensor({0.3f, -0.2f, 0.1f});
  EXPECT_TRUE(torch::allclose(mesh_edge_features(xs, ts), f, 1e-4, 1e-5));
  // At rest the current direction is the rest one and the length ratio is 1.
  auto fr = mesh_edge_features(test::to_tensor(s.rest.V).to(torch::kFloat32), t);
  EXPECT_TRUE(torch::allclose(fr.narrow(1, 0, 3), fr.narrow(1, 3, 3), 1e-5, 1e-6));
  EXPECT_TRUE(torch::allclose(fr.select(1, 6), torch::ones({fr.size(0)}), 1e-5, 1e-6));
}

TEST(Features, MaterialNormalisedToUnitRange) {
  MaterialRanges r;
  Material lo{r.density[0], r.mu[0], r.lambda[0], r.bending[0], 4.7e-4};
  Material hi{r.density[1], r.mu[1], r.lambda[1], r.bending[1], 4.7e-4};
  for (double v : normalised_material(lo, r)) EXPECT_NEAR(v, 0.0, 1e-12);
  for (double v : normalised_material(hi, r)) EXPECT_NEAR(v, 1.0, 1e-12);
  // Log scale: the geometric mean of mu's range sits in the middle.
  Material mid = lo;
  mid.mu = std::sqrt(r.mu[0] * r.mu[1]);
  EXPECT_NEAR(normalised_material(mid, r)[1], 0.5, 1e-12);
  r.bending = {1e-3, 1e-5};
  try {
    normalised_material(mid, r);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("model.material_ranges.bending"), std::string::npos);
  }
}

TEST(WorldEdges, PairsMatchBruteForce) {
  torch::manual_seed(3);
  auto x = torch::rand({60, 3}, torch::kFloat64) * 0.2, b = torch::rand({80, 3}, torch::kFloat64) * 0.2;
  auto d = torch::cdist(x, b);
  auto all = garment_body_pairs(x, b, 0.03, false);
  EXPECT_TRUE(torch::equal(all, (d < 0.03).nonzero()));
  // Nearest only: the garment vertices whose nearest body vertex is within the radius.
  auto [dmin, arg] = d.min(1);
  auto close = (dmin < 0.03).nonzero().squeeze(1);
  auto nearest = garment_body_pairs(x, b, 0.03, true);
  ASSERT_GT(close.size(0), 0);
  EXPECT_TRUE(torch::equal(nearest, torch::stack({close, arg.index_select(0, close)}, 1)));
  EXPECT_GT(all.size(0), nearest.size(0));
}

TEST(BuildGraph, FeaturesOfTheTinyScene) {
  auto s = tiny_scene(2, /*pins=*/true);
  s.state.effects.gravity = false;
  GarmentTopology t = build_garment_topology(s.rest);
  GraphBatch g = build_graph(s.state, t, GraphOptions{});
  const int64_t n = t.num_vertices;
  ASSERT_EQ(g.node_features.size(1), kVertexFeatureDim);
  ASSERT_EQ(g.num_garment_nodes, n);
  auto f = g.node_features;
  auto v = ((s.state.x - s.state.x_prev) / s.state.dt).to(torch::kFloat32);
  EXPECT_TRUE(torch::allclose(f.narrow(0, 0, n).narrow(1, 0, 3), v, 1e-5, 1e-5));
  // Types: rows 0..4 pinned, other garment rows garment, the rest body.
  EXPECT_EQ(f.narrow(0, 0, 5).select(1, 8).sum().item<float>(), 5.0f);
  EXPECT_EQ(f.narrow(0, 5, n - 5).select(1, 6).sum().item<float>(), float(n - 5));
  EXPECT_EQ(f.narrow(0, n, g.num_nodes() - n).select(1, 7).sum().item<float>(), float(g.num_nodes() - n));
  auto log_mass = torch::log(t.vertex_area * s.state.material.density);
  EXPECT_TRUE(torch::allclose(f.narrow(0, 0, n).select(1, 9), log_mass, 1e-5, 1e-6));
  // Gravity off: flag and vector zero; collision and friction on.
  EXPECT_EQ(f.select(1, 14).abs().sum().item<float>(), 0.0f);
  EXPECT_EQ(f.narrow(1, 18, 3).abs().sum().item<float>(), 0.0f);
  EXPECT_EQ(f.select(1, 15).min().item<float>(), 1.0f);
  // World edges: both directions, one per garment vertex near the body (to its nearest).
  auto pairs = garment_body_pairs(s.state.x, s.state.body.vertices, 0.03, true);
  ASSERT_GT(pairs.size(0), 0);
  ASSERT_LT(pairs.size(0), n);  // not every garment vertex is in contact
  EXPECT_EQ(g.num_world_edges(), 2 * pairs.size(0));
  EXPECT_EQ(g.num_nodes() - n, std::get<0>(torch::_unique(pairs.select(1, 1))).size(0));
  GraphOptions all_pairs;
  all_pairs.nearest_body_vertex_only = false;
  EXPECT_EQ(build_graph(s.state, t, all_pairs).num_world_edges(),
            2 * garment_body_pairs(s.state.x, s.state.body.vertices, 0.03, false).size(0));
  auto p = g.world_features.select(1, 3);
  EXPECT_LT(p.max().item<float>(), 0.03f);
  EXPECT_TRUE(torch::allclose(g.world_features.narrow(1, 0, 3).norm(2, 1), p, 1e-5, 1e-6));
}

// The tiny body is a flat grid at y = 0 (y = 0.004 at the next pose) with normals along +-y:
// the two normal-distance features are then the garment vertex's height over it, now and
// after coasting one step, times the normal's sign.
TEST(BuildGraph, WorldEdgesCarryTheHeightOverTheBodysTangentPlane) {
  auto s = tiny_scene(2);
  GarmentTopology t = build_garment_topology(s.rest);
  GraphOptions options;
  options.body_normal_distance = true;
  GraphBatch g = build_graph(s.state, t, options);
  ASSERT_EQ(g.world_features.size(1), options.world_edge_feature_dim());
  ASSERT_EQ(g.world_features.size(1), kWorldEdgeFeatureDim + kWorldEdgeNormalDistanceDim);
  ASSERT_GT(g.num_world_edges(), 0);
  const double sign = vertex_normals(s.state.body.vertices, s.state.body.faces)[0][1].item<double>() > 0 ? 1 : -1;
  const int64_t n = g.num_garment_nodes;
  auto x = s.state.x.to(torch::kFloat32), coast = (2 * s.state.x - s.state.x_prev).to(torch::kFloat32);
  for (int64_t e = 0; e < g.num_world_edges(); ++e) {
    int64_t r = g.world_receivers[e].item<int64_t>(), snd = g.world_senders[e].item<int64_t>();
    const int64_t garment = r < n ? r : snd;
    EXPECT_NEAR(g.world_features[e][8].item<float>(), sign * x[garment][1].item<float>(), 1e-5);
    EXPECT_NEAR(g.world_features[e][9].item<float>(), sign * (coast[garment][1].item<float>() - 0.004), 1e-5);
  }
  // Off (the default), the original 8 features, the same as the first 8 here.
  GraphBatch plain = build_graph(s.state, t, GraphOptions{});
  EXPECT_TRUE(torch::equal(plain.world_features, g.world_features.narrow(1, 0, 8)));
}

TEST(BuildGraph, NoBodyEffectsMeansNoWorldEdges) {
  auto s = tiny_scene(4);
  s.state.effects.collision = s.state.effects.friction = false;
  GarmentTopology t = build_garment_topology(s.rest);
  GraphBatch g = build_graph(s.state, t, GraphOptions{});
  EXPECT_EQ(g.num_world_edges(), 0);
  EXPECT_EQ(g.num_nodes(), t.num_vertices);
  // The topology's index tensors are shared, not copied per frame.
  EXPECT_EQ(g.mesh_senders.data_ptr(), t.senders.data_ptr());
}

TEST(BuildGraph, BadFrameStateIsAOneLineError) {
  auto s = tiny_scene(5);
  GarmentTopology t = build_garment_topology(s.rest);
  s.state.x = s.state.x.narrow(0, 0, 7);
  EXPECT_THROW(build_graph(s.state, t, GraphOptions{}), Error);
  auto s2 = tiny_scene(5);
  s2.state.x[3][1] = std::nan("");
  try {
    build_graph(s2.state, t, GraphOptions{});
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not finite"), std::string::npos);
  }
}

TEST(OnlineNormalizer, AccumulatesThenFreezes) {
  OnlineNormalizer norm(2, /*max_accumulations=*/2, 1e-8);
  torch::manual_seed(6);
  auto a = torch::randn({50, 2}) * 3 + 1, b = torch::randn({30, 2}) * 2 - 1;
  norm->train();
  norm(a);
  norm(b);
  auto all = torch::cat({a, b}).to(torch::kFloat64);
  EXPECT_TRUE(torch::allclose(norm->mean(), all.mean(0), 1e-6, 1e-6));
  EXPECT_TRUE(torch::allclose(norm->std(), all.std(0, /*unbiased=*/false), 1e-6, 1e-6));
  EXPECT_TRUE(norm->frozen());
  auto mean = norm->mean().clone();
  norm(torch::randn({20, 2}) + 100);  // frozen: ignored
  EXPECT_TRUE(torch::equal(norm->mean(), mean));
  auto z = norm(all.to(torch::kFloat32));
  EXPECT_TRUE(torch::allclose(z.mean(0), torch::zeros({2}), 1e-4, 1e-4));
  // Evaluation mode never accumulates.
  OnlineNormalizer eval_norm(2, 10, 1e-8);
  eval_norm->eval();
  eval_norm(a);
  EXPECT_EQ(eval_norm->count.item<double>(), 0.0);
}

}  // namespace
}  // namespace pb4u

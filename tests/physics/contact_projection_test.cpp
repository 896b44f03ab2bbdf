// The inference-time contact projection against closed forms on a sphere body: vertices inside
// or within the gap end exactly `gap` outside the tessellated surface along the radius, the rest
// and the pinned ones do not move, and the collision term's measure is satisfied afterwards.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "pb4u/data/dataset.h"
#include "pb4u/rollout/rollout.h"
#include "pb4u/graph/garment_topology.h"
#include "pb4u/physics/collision_energy.h"
#include "pb4u/physics/contact_projection.h"
#include "pb4u/physics/penetration.h"
#include "pb4u/spatial/signed_distance_to_surface.h"
#include "pb4u/util/eigen_tensor.h"
#include "physics_test_util.h"
#include "test_util.h"

namespace pb4u {
namespace {

constexpr double kR = 0.3;

// A sphere body (static: the same at t and t + dt) and a garment state with one vertex per
// radius, in random directions around the centre.
struct SphereScene {
  TriMesh body;
  FrameState state;
  Eigen::RowVector3d centre{0.1, 1.0, -0.2};
  Eigen::MatrixXd x;  // n x 3: the network's predicted x_{t+1}

  explicit SphereScene(const std::vector<double>& radii) {
    body = test::icosphere(kR, 4, centre);
    std::mt19937 rng(5);
    std::normal_distribution<double> n(0, 1);
    x.resize(radii.size(), 3);
    for (size_t i = 0; i < radii.size(); ++i) x.row(i) = centre + radii[i] * Eigen::RowVector3d(n(rng), n(rng), n(rng)).normalized();
    state.x = matrix_to_tensor(x);
    state.x_prev = state.x.clone();
    state.effects.collision = true;
    state.body.vertices = matrix_to_tensor(body.V);
    state.body.next_vertices = state.body.vertices;
    state.body.faces = index_matrix_to_tensor(body.F);
  }
};

TEST(ContactProjection, InsideAndNearVerticesEndGapOutsideTheSurface) {
  const double gap = 0.002;
  // 0.5 R and 0.95 R inside, 1.002 R (0.6 mm out: within the gap), 1.1 R and 3 R well outside.
  const std::vector<double> radii = {0.5 * kR, 0.95 * kR, 1.002 * kR, 1.1 * kR, 3 * kR};
  SphereScene s(radii);
  const Eigen::MatrixXd out = tensor_to_matrix(project_out_of_body(matrix_to_tensor(s.x), s.state, nullptr, gap));
  const Eigen::VectorXd d = signed_distance_to_surface(out, s.body.V, s.body.F);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(d(i), gap, 1e-9) << "vertex " << i << " ends exactly gap outside the tessellated surface";
    // Along the radius, within the tessellation's ~0.1% of R.
    const Eigen::RowVector3d before = (s.x.row(i) - s.centre).normalized(), after = (out.row(i) - s.centre).normalized();
    EXPECT_GT(before.dot(after), std::cos(0.02)) << "vertex " << i;
  }
  for (int i = 3; i < 5; ++i) EXPECT_EQ((out.row(i) - s.x.row(i)).norm(), 0.0) << "vertex " << i << " was outside";
  const PenetrationFigures p = garment_penetration(out, s.body.V, s.body.F);
  EXPECT_EQ(p.penetrating_fraction, 0.0);
}

TEST(ContactProjection, PinnedVerticesNoBodyAndZeroGapLeaveTheStepAsItIs) {
  SphereScene s({0.5 * kR, 0.9 * kR});
  const torch::Tensor x = matrix_to_tensor(s.x);
  s.state.pinned = torch::tensor({true, false});
  const Eigen::MatrixXd out = tensor_to_matrix(project_out_of_body(x, s.state, nullptr, 0.002));
  EXPECT_EQ((out.row(0) - s.x.row(0)).norm(), 0.0) << "a pinned vertex follows its target";
  EXPECT_GT((out.row(1) - s.x.row(1)).norm(), 0.09 * kR - 1e-3);
  EXPECT_TRUE(project_out_of_body(x, s.state, nullptr, 0.0).equal(x));
  FrameState no_body = s.state;
  no_body.body = BodyFrame{};
  EXPECT_TRUE(project_out_of_body(x, no_body, nullptr, 0.002).equal(x));
}

// A garment at x ((n, 3) m) beside a static body, with collision on.
FrameState static_body_state(const torch::Tensor& x, const TriMesh& body) {
  FrameState state;
  state.x = state.x_prev = x;
  state.effects.collision = true;
  state.body.vertices = state.body.next_vertices = matrix_to_tensor(body.V);
  state.body.faces = index_matrix_to_tensor(body.F);
  return state;
}

// The step's contact, matched at the state's x as in a rollout.
BodyContact contact_at(const FrameState& state) {
  const PhysicsConfig physics;
  return query_body_contact(state.x, state.body, physics.friction.contact_radius, physics.degenerate_area);
}

// The collision energy of the step x -> x_next ((n, 3) each) before and after projecting x_next
// out of `body` (static); the contact is matched at x, as in a rollout.
std::pair<double, double> collision_before_and_after(const torch::Tensor& x, const torch::Tensor& x_next,
                                                     const TriMesh& body) {
  const FrameState state = static_body_state(x, body);
  const BodyContact contact = contact_at(state);
  const double eps = PhysicsConfig().collision.eps;
  return {collision_energy(x_next, contact, eps, 1.0).item<double>(),
          collision_energy(project_out_of_body(x_next, state, &contact, eps), contact, eps, 1.0).item<double>()};
}

// A garment step on a static body: every body vertex moved ~1 cm in a random direction at t
// (x), and ~1 cm more at t + dt (x_next).
std::pair<Eigen::MatrixXd, Eigen::MatrixXd> jittered_step(const TriMesh& body, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> offset(0.0, 0.01);
  Eigen::MatrixXd x = body.V, x_next(body.V.rows(), 3);
  for (Eigen::Index i = 0; i < x.rows(); ++i) x.row(i) += Eigen::RowVector3d(offset(rng), offset(rng), offset(rng));
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    x_next.row(i) = x.row(i) + Eigen::RowVector3d(offset(rng), offset(rng), offset(rng));
  return {x, x_next};
}

TEST(ContactProjection, AfterwardsTheCollisionTermMeasuresNothing) {
  // With the gap at the penalty's eps the projected step has zero collision energy: on a sphere,
  // and on the tiny dataset's mannequin, whose armpits and crotch are concave. There the exact
  // pass can leave a vertex behind the plane of the face it was matched to at t, which pass 3
  // corrects.
  SphereScene s({0.6 * kR, 0.8 * kR, 0.99 * kR, 1.001 * kR, 1.2 * kR});
  const torch::Tensor on_sphere = matrix_to_tensor(s.x);
  const auto sphere = collision_before_and_after(on_sphere, on_sphere, s.body);
  EXPECT_GT(sphere.first, 0.0);
  EXPECT_LT(sphere.second, 1e-15);

  const Dataset data = read_dataset(test::tiny_dataset());
  const TriMesh& body = data.bodies.front().body.mesh;
  const auto [x, x_next] = jittered_step(body, 2);
  const auto mannequin = collision_before_and_after(matrix_to_tensor(x), matrix_to_tensor(x_next), body);
  EXPECT_GT(mannequin.first, 0.0);
  EXPECT_LT(mannequin.second, 1e-15);
}

// A body prepared once (as the rounds of a step's constraints use it) projects exactly as the
// body prepared per call: the same step, bit for bit, on the concave mannequin.
TEST(ContactProjection, APreparedBodyGivesTheSameStep) {
  const Dataset data = read_dataset(test::tiny_dataset());
  const TriMesh& body = data.bodies.front().body.mesh;
  const auto [x, x_next] = jittered_step(body, 3);
  const FrameState state = static_body_state(matrix_to_tensor(x), body);
  const BodyContact contact = contact_at(state);
  const ProjectionSurface prepared(state.body);
  const torch::Tensor step = matrix_to_tensor(x_next);
  const torch::Tensor once = project_out_of_body(step, state, &contact, 0.004);
  ASSERT_FALSE(once.equal(step)) << "the case must move vertices";
  EXPECT_TRUE(project_out_of_body(step, state, &contact, 0.004, &prepared).equal(once));
  EXPECT_TRUE(project_out_of_body(step, state, nullptr, 0.004, &prepared).equal(project_out_of_body(step, state, nullptr, 0.004)));
}

// Pass 3 (the plane pass again) never pushes a vertex into the body. Two spheres 5 cm apart:
// a vertex matched at t to a face of sphere A (up and to the right of its centre) lands inside
// sphere B at t + dt. The exact pass moves it out of B, to the gap outside B's left pole, which
// is behind the plane of its A face; pushing it along that face's normal to the gap in front of
// the plane would put it ~6 mm back into B. It stays outside both, where the plane measure is
// not met.
TEST(ContactProjection, ThePlanePassAgainNeverPushesAVertexIntoTheBody) {
  const double gap = 0.002;
  const TriMesh a = test::icosphere(kR, 4, Eigen::RowVector3d(0, 1, 0));
  const TriMesh b = test::icosphere(kR, 4, Eigen::RowVector3d(0.65, 1, 0));
  TriMesh body;
  body.V.resize(a.V.rows() + b.V.rows(), 3);
  body.V << a.V, b.V;
  body.F.resize(a.F.rows() + b.F.rows(), 3);
  body.F << a.F, (b.F.array() + int(a.V.rows())).matrix();
  Eigen::MatrixXd x(1, 3), x_next(1, 3);
  x << 0.31, 1.2, 0;        // 7 cm from A along ~(0.84, 0.54, 0), 14 cm from B
  x_next << 0.45, 1.0, 0;  // 5 cm inside B
  const FrameState state = static_body_state(matrix_to_tensor(x), body);
  const BodyContact contact = contact_at(state);
  const Eigen::RowVector3d normal = tensor_to_matrix(contact.normal).row(0);
  ASSERT_GT(normal.dot(Eigen::RowVector3d(0.84, 0.54, 0).normalized()), 0.99) << "matched to a face of A";
  const Eigen::MatrixXd out = tensor_to_matrix(project_out_of_body(matrix_to_tensor(x_next), state, &contact, gap));
  EXPECT_NEAR(signed_distance_to_surface(out, body.V, body.F)(0), gap, 1e-9) << "left where the exact pass put it";
  EXPECT_NEAR(out(0, 0), 0.35 - gap, 1e-3) << "at B's left pole";
  EXPECT_GT(collision_energy(matrix_to_tensor(out), contact, gap, 1.0).item<double>(), 0.0)
      << "A's plane is not met there: meeting it would have meant entering B";
}

// Through the network's stepper: a model file with contact_projection > 0 keeps a cloth that
// starts sunk 2 cm into a sphere outside it on every frame; the same weights without it do not.
TEST(ContactProjection, TheNetworkStepperProjectsWhenTheModelFileSaysSo) {
  TriMesh garment;
  const FrameState start = test::cloth_above_sphere(8, 0.4, 0.3, -0.02, 3, &garment);
  const TriMesh sphere = test::icosphere(0.3, 3, Eigen::RowVector3d::Zero());
  RolloutInput in;
  in.garment_rest = garment;
  in.x0 = in.x_prev = tensor_to_matrix(start.x);
  in.effects = start.effects;
  in.steps = 3;
  in.body.assign(in.steps + 1, sphere.V);
  in.body_faces = sphere.F;
  const GarmentTopology topology = build_garment_topology(garment);
  torch::manual_seed(3);
  ModelFile m;
  m.config.latent = 16;
  m.config.num_blocks = 1;
  m.model = Pb4uNet(m.config);
  m.model->calibrate(topology.mean_edge_length);
  m.model->eval();
  auto inside_on_frames = [&](double gap) {
    m.config.contact_projection = gap;
    std::vector<double> inside;
    for (const auto& p : run_rollout(in, network_stepper(m, topology), PhysicsConfig{}).penetration)
      inside.push_back(p.penetrating_fraction);
    return inside;
  };
  const std::vector<double> projected = inside_on_frames(0.002), raw = inside_on_frames(0.0);
  ASSERT_EQ(projected.size(), 3u);
  for (double f : projected) EXPECT_EQ(f, 0.0);
  EXPECT_GT(raw.front(), 0.0) << "without the projection the sunk cloth is still inside after one step";
}

}  // namespace
}  // namespace pb4u

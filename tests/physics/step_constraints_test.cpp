// The step constraints (strain limit alternated with the contact projection) on a closed form:
// a cloth resting on a sphere, one vertex of which the "network" throws into the sphere near its
// side. The projection alone puts that vertex on the side of the sphere, its edges stretched
// several times; alternated with the strain limit, the step ends outside the sphere with every
// edge within the limit. Without a body or a strain limit it reduces to one of the two.
#include <gtest/gtest.h>

#include "pb4u/graph/garment_topology.h"
#include "pb4u/physics/contact_projection.h"
#include "pb4u/physics/step_constraints.h"
#include "pb4u/physics/strain_limiting.h"
#include "pb4u/spatial/signed_distance_to_surface.h"
#include "pb4u/util/eigen_tensor.h"
#include "physics_test_util.h"

namespace pb4u {
namespace {

constexpr double kRadius = 0.3, kGap = 0.002, kLimit = 0.1;

struct ThrownVertex {
  TriMesh cloth, sphere = test::icosphere(kRadius, 4, Eigen::RowVector3d::Zero());
  FrameState state = test::cloth_above_sphere(12, 0.48, kRadius, 0.005, 4, &cloth);
  GarmentTopology topology = build_garment_topology(cloth);
  torch::Tensor x_next;
  ThrownVertex() {
    Eigen::MatrixXd x = cloth.V;
    // The centre vertex (grid 12: row 6, column 6), 6 cm inside the sphere's side.
    x.row(6 * 13 + 6) << kRadius - 0.06, 0.05, 0.0;
    x_next = matrix_to_tensor(x);
  }
  double max_strain(const torch::Tensor& x) const { return limit_edge_strain(x, topology, torch::Tensor(), kLimit, 0).max_strain; }
  double min_distance(const torch::Tensor& x) const {
    return signed_distance_to_surface(tensor_to_matrix(x), sphere.V, sphere.F).minCoeff();
  }
};

TEST(StepConstraints, ProjectionAloneStretchesWhereTheLimitAndProjectionTogetherDoNot) {
  ThrownVertex s;
  const torch::Tensor projected = project_out_of_body(s.x_next, s.state, nullptr, kGap);
  EXPECT_GT(s.max_strain(projected), 1.0) << "the projection alone leaves the thrown vertex's edges stretched";
  const torch::Tensor both = constrain_step(s.x_next, s.state, nullptr, s.topology, kLimit, kGap);
  EXPECT_LE(s.max_strain(both), 1.1 * kLimit);
  EXPECT_GE(s.min_distance(both), kGap - 1e-9) << "the step ends projected: every vertex outside";
}

TEST(StepConstraints, WithoutABodyOrALimitItIsTheOtherConstraintAlone) {
  ThrownVertex s;
  const torch::Tensor projected = project_out_of_body(s.x_next, s.state, nullptr, kGap);
  EXPECT_TRUE(constrain_step(s.x_next, s.state, nullptr, s.topology, 0.0, kGap).equal(projected));
  FrameState no_body = s.state;
  no_body.body = BodyFrame{};
  const torch::Tensor limited = limit_edge_strain(s.x_next, s.topology, torch::Tensor(), kLimit).x;
  EXPECT_TRUE(constrain_step(s.x_next, no_body, nullptr, s.topology, kLimit, kGap).equal(limited));
  EXPECT_TRUE(constrain_step(s.x_next, no_body, nullptr, s.topology, 0.0, kGap).equal(s.x_next));
}

}  // namespace
}  // namespace pb4u

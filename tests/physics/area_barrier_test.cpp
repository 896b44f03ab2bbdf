// The barrier against collapse: a triangle's area and its derivatives against closed forms and
// finite differences, the step filter against the closed form, and the solver keeping a
// triangle from collapsing that a load inside the solve drags through its opposite edge.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <random>

#include "pb4u/physics/area_barrier.h"
#include "pb4u/physics/reference_solver.h"
#include "pb4u/util/eigen_tensor.h"
#include "physics_test_util.h"
#include "test_util.h"

namespace pb4u {
namespace {

using Vec9 = Eigen::Matrix<double, 9, 1>;
using Mat9 = Eigen::Matrix<double, 9, 9>;

double area_of(const Vec9& x) { return triangle_area(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6)); }

TEST(AreaBarrier, TriangleAreaAndItsDerivativesMatchClosedFormsAndFiniteDifferences) {
  // The right triangle with legs 0.3 and 0.4 in the x-y plane: area 0.06; moving the apex along
  // y changes it by 0.3 / 2 per metre; moving it out of the plane, not at first order.
  Vec9 x;
  x << 0, 0, 0, 0.3, 0, 0, 0, 0.4, 0;
  Vec9 g;
  Mat9 H;
  EXPECT_NEAR(triangle_area(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6), &g, &H), 0.06, 1e-15);
  EXPECT_NEAR(g(7), 0.15, 1e-15);
  EXPECT_NEAR(g(8), 0.0, 1e-15);
  EXPECT_NEAR(g.segment<3>(0).sum() + g.segment<3>(3).sum() + g.segment<3>(6).sum(), 0.0, 1e-15);  // translation
  // A general triangle: the gradient and the exact Hessian against central differences.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  for (int k = 0; k < 9; ++k) x(k) = u(rng);
  triangle_area(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6), &g, &H);
  const double h = 1e-6;
  for (int k = 0; k < 9; ++k) {
    Vec9 up = x, down = x;
    up(k) += h;
    down(k) -= h;
    EXPECT_NEAR(g(k), (area_of(up) - area_of(down)) / (2 * h), 1e-8) << k;
    Vec9 gu, gd;
    triangle_area(up.segment<3>(0), up.segment<3>(3), up.segment<3>(6), &gu);
    triangle_area(down.segment<3>(0), down.segment<3>(3), down.segment<3>(6), &gd);
    const Vec9 column = (gu - gd) / (2 * h);
    for (int r = 0; r < 9; ++r) EXPECT_NEAR(H(r, k), column(r), 1e-6 * std::max(1.0, std::abs(column(r)))) << r << " " << k;
  }
  // Degenerate (three points on a line): zero area, zero derivatives, no NaN.
  x << 0, 0, 0, 1, 0, 0, 2, 0, 0;
  EXPECT_EQ(triangle_area(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6), &g, &H), 0.0);
  EXPECT_TRUE(g.isZero() && H.isZero());
}

TEST(AreaBarrier, ItsGradientAndCurvatureAreTheEnergysDerivativesAndItIsInfiniteAtCollapse) {
  // A strip of two triangles squashed in y to 5% of its rest area: inside the band (10%).
  TriMesh g = test::grid_mesh(1, 0.1);
  Eigen::VectorXd A0(g.F.rows());
  for (Eigen::Index f = 0; f < g.F.rows(); ++f)
    A0(f) = triangle_area(g.V.row(g.F(f, 0)).transpose(), g.V.row(g.F(f, 1)).transpose(), g.V.row(g.F(f, 2)).transpose());
  Eigen::MatrixXd x = g.V;
  x.col(2) *= 0.05;  // grid_mesh lies in x-z
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> noise(-1e-5, 1e-5);
  for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] += noise(rng);
  const AreaBarrierSettings s{0.1, 1e4};
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(x.rows(), 3);
  Eigen::VectorXd curvature = Eigen::VectorXd::Zero(x.rows());
  const AreaBarrierValue v = area_barrier(x, g.F, A0, s, {}, &G, &curvature);
  ASSERT_EQ(v.active, 2);
  ASSERT_GT(v.energy, 0);
  EXPECT_NEAR(v.min_ratio, 0.05, 2e-3);
  const double h = 1e-8;
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    for (int c = 0; c < 3; ++c) {
      Eigen::MatrixXd up = x, down = x;
      up(i, c) += h;
      down(i, c) -= h;
      const double fd = (area_barrier(up, g.F, A0, s, {}).energy - area_barrier(down, g.F, A0, s, {}).energy) / (2 * h);
      EXPECT_NEAR(G(i, c), fd, 1e-5 * std::max(1.0, std::abs(fd))) << i << " " << c;
    }
  // The projected Hessian is positive semidefinite and, at a vertex moved along the area's
  // gradient alone, as curved as the energy (its second difference).
  CoordinateHessian H(int(x.rows()));
  area_barrier(x, g.F, A0, s, {}, nullptr, nullptr, &H);
  std::vector<int> rows(size_t(x.rows()));
  for (size_t i = 0; i < rows.size(); ++i) rows[i] = int(i);
  const Eigen::MatrixXd dense = Eigen::MatrixXd(H.matrix(rows));
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(dense).eigenvalues().minCoeff(), -1e-6 * dense.norm());
  // Collapsed: infinite, unless the face is left out; above the band: zero.
  Eigen::MatrixXd flat = g.V;
  flat.col(2).setZero();
  EXPECT_TRUE(std::isinf(area_barrier(flat, g.F, A0, s, {}).energy));
  EXPECT_EQ(area_barrier(flat, g.F, A0, s, {1, 1}).energy, 0.0);
  EXPECT_EQ(area_barrier(g.V, g.F, A0, s, {}).energy, 0.0);
  EXPECT_EQ(faces_below_area(flat, g.F, A0, 0.0), (std::vector<char>{1, 1}));
  EXPECT_EQ(faces_below_area(x, g.F, A0, 0.0), (std::vector<char>{0, 0}));
}

TEST(AreaBarrier, TheStepStopsShortOfACollapseAsTheClosedFormSays) {
  Eigen::MatrixXd x(3, 3), dx = Eigen::MatrixXd::Zero(3, 3);
  x << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  const Eigen::MatrixXi F = (Eigen::MatrixXi(1, 3) << 0, 1, 2).finished();
  dx.row(2) << 0, -2, 0;  // the apex reaches the opposite edge at half the step
  EXPECT_NEAR(max_area_step(x, dx, F, {}), 0.8 * 0.5, 1e-12);
  dx.row(2) << 3, -2, 0;  // across it, sliding along: still at half
  EXPECT_NEAR(max_area_step(x, dx, F, {}), 0.8 * 0.5, 1e-12);
  // Both legs shrinking towards vertex 0 (the area goes as (1 - t)^2): at t = 1, the whole step
  // is 0.8 of it.
  dx.row(1) << -1, 0, 0;
  dx.row(2) << 0, -1, 0;
  EXPECT_NEAR(max_area_step(x, dx, F, {}), 0.8, 1e-7);
  dx.setZero();
  dx.row(2) << 0, 0, 1;  // lifted out of the plane: the area grows
  EXPECT_EQ(max_area_step(x, dx, F, {}), 1.0);
  dx.row(2) << 0, 0.5, 0;  // taller
  EXPECT_EQ(max_area_step(x, dx, F, {}), 1.0);
  dx.row(2) << 0, -2, 0;
  EXPECT_EQ(max_area_step(x, dx, F, {1}), 1.0);  // left out
}

// A spring pulling one vertex towards a target (N/m): a load inside the solve, not in its start.
// It also keeps the smallest area the triangle (0, 1, 2) had at any state the solver evaluated.
class SpringToTarget : public PhysicsTerm {
 public:
  SpringToTarget(int64_t vertex, torch::Tensor target, double stiffness, double* smallest_area)
      : vertex_(vertex), target_(std::move(target)), stiffness_(stiffness), smallest_area_(smallest_area) {}
  std::string name() const override { return "spring"; }
  torch::Tensor energy(const torch::Tensor& x_next, const FrameState&, const ClothGeometry&,
                       const BodyContact*) const override {
    const Eigen::MatrixXd X = tensor_to_matrix(x_next.detach());
    *smallest_area_ = std::min(*smallest_area_, triangle_area(X.row(0).transpose(), X.row(1).transpose(), X.row(2).transpose()));
    return 0.5 * stiffness_ * (x_next[vertex_] - target_).pow(2).sum();
  }

 private:
  int64_t vertex_;
  torch::Tensor target_;
  double stiffness_;
  double* smallest_area_;
};

// One soft triangle (area 0.0025 m^2) with two vertices pinned and the third pulled by a stiff
// spring to a point beyond the edge between them. Without the area barrier the solve drags it
// through that edge in its plane: it collapses on the way and ends turned over. With it, no
// state the solver evaluates comes near a collapse, under either step. (Newton, whose Hessian
// sees the spring's pull in its plane and none across it, then finds the way round: the apex
// leaves the plane and swings about the pinned edge to the spring's side, a rotation, not a
// collapse.)
TEST(AreaBarrier, TheSolverKeepsATrianglePulledThroughItsOppositeEdgeFromCollapsing) {
  TriMesh g;
  g.V.resize(3, 3);
  g.V << 0, 0, 0, 0.1, 0, 0, 0.05, 0.05, 0;
  g.F = (Eigen::MatrixXi(1, 3) << 0, 1, 2).finished();
  const ClothGeometry cloth = make_cloth_geometry(g);
  struct Pulled {
    Eigen::MatrixXd x;
    double smallest_ratio = 1;  // over every evaluated state
    SolverResult result;
  };
  auto pull = [&](double gap, const std::string& step) {
    FrameState state = test::resting_state(test::positions_tensor(g.V));
    state.material.mu = state.material.lambda = 1;
    state.effects.pins = true;
    state.pinned = torch::tensor({true, true, false});
    state.pin_targets = state.x.clone();
    PhysicsConfig config;
    config.solver.area_barrier_gap = gap;
    config.solver.step = step;
    Pulled out;
    double smallest = 1;
    TermList terms = build_terms(state.effects, config);
    terms.push_back(
        std::make_unique<SpringToTarget>(2, torch::tensor({0.05, -0.05, 0.0}, torch::kFloat64), 100.0, &smallest));
    out.result = solve_reference_frame(state, cloth, terms, config);
    out.x = tensor_to_matrix(out.result.x_next);
    out.smallest_ratio = smallest / 0.0025;
    return out;
  };
  const Pulled free = pull(0, "quasi_newton");
  ASSERT_LT(free.x(2, 1), -0.04) << "without the barrier the spring must drag the apex through the edge";
  ASSERT_TRUE(free.x.col(2).isZero()) << "in the plane: so it passed through a collapse";
  for (const std::string step : {"quasi_newton", "newton"}) {
    const Pulled held = pull(0.1, step);
    EXPECT_GT(held.smallest_ratio, 0.01) << step;
    EXPECT_GT(held.result.min_area_ratio, 0.01) << step;
    EXPECT_EQ(held.result.area_excluded, 0) << step;
    EXPECT_TRUE(held.result.converged) << step;
  }
  // Quasi-Newton stays in the plane: held on its side, inside the barrier's band.
  const Pulled in_plane = pull(0.1, "quasi_newton");
  EXPECT_TRUE(in_plane.x.col(2).isZero());
  EXPECT_GT(in_plane.x(2, 1), 0);
  EXPECT_LT(in_plane.result.min_area_ratio, 0.1);
}

}  // namespace
}  // namespace pb4u

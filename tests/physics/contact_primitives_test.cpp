// The pieces of intersection-free contact, each against a closed form: point-triangle and
// edge-edge distances and their gradients, IPC's barrier and its derivatives, and additive CCD
// on crossing, grazing and parallel trajectories.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "pb4u/physics/additive_ccd.h"
#include "pb4u/physics/barrier.h"
#include "pb4u/physics/primitive_distance.h"

namespace pb4u {
namespace {

using V = Eigen::Vector3d;
using Four = std::array<V, 4>;

const V ta(0, 0, 0), tb(1, 0, 0), tc(0, 1, 0);

// Central differences of a distance function of the 12 coordinates.
template <class F>
Eigen::Matrix<double, 12, 1> numeric_gradient(const F& distance, Four x) {
  Eigen::Matrix<double, 12, 1> g;
  const double h = 1e-7;
  for (int i = 0; i < 12; ++i) {
    Four plus = x, minus = x;
    plus[i / 3](i % 3) += h;
    minus[i / 3](i % 3) -= h;
    g(i) = (distance(plus) - distance(minus)) / (2 * h);
  }
  return g;
}

TEST(PrimitiveDistance, PointTriangleInEveryRegion) {
  struct Case {
    V p;
    double d;
  };
  const std::vector<Case> cases = {
      {{0.2, 0.3, 0.5}, 0.5},                           // over the interior
      {{0.2, 0.3, -0.25}, 0.25},                        // under it
      {{0.5, -0.4, 0.3}, 0.5},                          // outside edge ab
      {{1, 1, 0.2}, std::sqrt(0.5 + 0.04)},             // outside edge bc
      {{-0.3, 0.5, 0.4}, 0.5},                          // outside edge ca
      {{-0.3, -0.4, 0}, 0.5},                           // corner a
      {{1.3, -0.4, 0}, 0.5},                            // corner b
      {{-0.4, 1.3, 0}, 0.5},                            // corner c
  };
  for (const auto& c : cases) {
    const PrimitiveDistance d = point_triangle_distance(c.p, ta, tb, tc);
    EXPECT_NEAR(d.distance, c.d, 1e-14) << c.p.transpose();
    // The weights rebuild the closest-point difference.
    const V r = d.weights(0) * c.p + d.weights(1) * ta + d.weights(2) * tb + d.weights(3) * tc;
    EXPECT_NEAR(r.norm(), c.d, 1e-14);
    const auto numeric = numeric_gradient(
        [](const Four& x) { return point_triangle_distance(x[0], x[1], x[2], x[3]).distance; }, {c.p, ta, tb, tc});
    EXPECT_LT((d.gradient - numeric).cwiseAbs().maxCoeff(), 1e-6) << c.p.transpose();
  }
}

TEST(PrimitiveDistance, EdgeEdgeCrossingParallelAndClamped) {
  // Perpendicular segments crossing over each other at height h.
  EXPECT_NEAR(edge_edge_distance({-1, 0, 0}, {1, 0, 0}, {0, -1, 0.3}, {0, 1, 0.3}).distance, 0.3, 1e-14);
  // Parallel, overlapping in x, 0.3 apart.
  EXPECT_NEAR(edge_edge_distance({0, 0, 0}, {1, 0, 0}, {0.5, 0.3, 0}, {2, 0.3, 0}).distance, 0.3, 1e-14);
  // Parallel, not overlapping: end to end.
  EXPECT_NEAR(edge_edge_distance({0, 0, 0}, {1, 0, 0}, {1.4, 0.3, 0}, {2, 0.3, 0}).distance, 0.5, 1e-14);
  // Skew, the closest point of the first at its end a1.
  EXPECT_NEAR(edge_edge_distance({0, 0, 0}, {1, 0, 0}, {2, -1, 0.1}, {2, 1, 0.1}).distance, std::sqrt(1.01), 1e-14);
  // A zero-length segment is a point.
  EXPECT_NEAR(edge_edge_distance({0.5, 0.2, 0}, {0.5, 0.2, 0}, {0, 0, 0}, {1, 0, 0}).distance, 0.2, 1e-14);
}

TEST(PrimitiveDistance, GradientsMatchFiniteDifferences) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  auto random_point = [&] { return V(u(rng), u(rng), u(rng)); };
  for (int trial = 0; trial < 200; ++trial) {
    const Four x{random_point(), random_point(), random_point(), random_point()};
    const PrimitiveDistance pt = point_triangle_distance(x[0], x[1], x[2], x[3]);
    const auto pt_numeric = numeric_gradient(
        [](const Four& y) { return point_triangle_distance(y[0], y[1], y[2], y[3]).distance; }, x);
    EXPECT_LT((pt.gradient - pt_numeric).cwiseAbs().maxCoeff(), 1e-5) << "point-triangle trial " << trial;
    const PrimitiveDistance ee = edge_edge_distance(x[0], x[1], x[2], x[3]);
    const auto ee_numeric = numeric_gradient(
        [](const Four& y) { return edge_edge_distance(y[0], y[1], y[2], y[3]).distance; }, x);
    EXPECT_LT((ee.gradient - ee_numeric).cwiseAbs().maxCoeff(), 1e-5) << "edge-edge trial " << trial;
  }
}

TEST(Barrier, ClosedFormsAndDerivatives) {
  const double d_hat = 1e-3;
  EXPECT_EQ(barrier(d_hat, d_hat), 0);
  EXPECT_EQ(barrier(2 * d_hat, d_hat), 0);
  EXPECT_EQ(barrier_derivative(d_hat, d_hat), 0);
  EXPECT_NEAR(barrier_second_derivative(d_hat * (1 - 1e-12), d_hat), 0, 1e-9);  // C2 at d_hat
  // b(d_hat / e) = d_hat^2 (1 - 1/e)^2.
  EXPECT_NEAR(barrier(d_hat / std::exp(1.0), d_hat), d_hat * d_hat * std::pow(1 - std::exp(-1.0), 2), 1e-18);
  EXPECT_TRUE(std::isinf(barrier(0, d_hat)));
  double previous = 0;
  for (double d = 0.95 * d_hat; d > 1e-9; d *= 0.5) {
    const double h = d * 1e-5;
    EXPECT_NEAR(barrier_derivative(d, d_hat), (barrier(d + h, d_hat) - barrier(d - h, d_hat)) / (2 * h),
                1e-6 * std::abs(barrier_derivative(d, d_hat)) + 1e-12)
        << d;
    EXPECT_NEAR(barrier_second_derivative(d, d_hat),
                (barrier_derivative(d + h, d_hat) - barrier_derivative(d - h, d_hat)) / (2 * h),
                1e-5 * std::abs(barrier_second_derivative(d, d_hat)) + 1e-9)
        << d;
    EXPECT_LT(barrier_derivative(d, d_hat), 0);  // pushes apart
    EXPECT_GT(barrier(d, d_hat), previous);       // grows as d falls
    previous = barrier(d, d_hat);
  }
}

TEST(AdditiveCcd, PointThroughATriangleStopsBeforeIt) {
  // Height 1 above the interior, moving 2 down: it would cross at t = 0.5.
  const V p(0.2, 0.2, 1), dp(0, 0, -2), zero = V::Zero();
  const double t = point_triangle_ccd(p, ta, tb, tc, dp, zero, zero, zero);
  EXPECT_LT(t, 0.5);
  EXPECT_GE(t, 0.9 * 0.45);  // ACCD's first advance alone reaches (1 - keep) t* = 0.45
  EXPECT_GT(point_triangle_distance(p + t * dp, ta, tb, tc).distance, 0.05);
  // The triangle moving up to meet it: the impact at t = 0.25 comes first.
  const V up(0, 0, 2);
  const double t2 = point_triangle_ccd(p, ta, tb, tc, dp, up, up, up);
  EXPECT_LT(t2, 0.25);
  EXPECT_GT(t2, 0.2);
  // Touching at the start: no step is safe.
  EXPECT_EQ(point_triangle_ccd(V(0.2, 0.2, 0), ta, tb, tc, dp, zero, zero, zero), 0);
}

// A line search's use of CCD: step to the safe time, ask again from there for the rest of the
// step. Returns the fraction of the step reached after `calls` calls.
template <class Ccd>
double advance(Four x, const Four& dx, const Ccd& ccd, int calls) {
  double done = 0;
  for (int k = 0; k < calls && done < 1; ++k) {
    Four rest;
    for (int i = 0; i < 4; ++i) rest[i] = (1 - done) * dx[i];
    const double t = ccd(x, rest);
    for (int i = 0; i < 4; ++i) x[i] += t * rest[i];
    done += t * (1 - done);
  }
  return done;
}

double point_triangle(const Four& x, const Four& d) {
  return point_triangle_ccd(x[0], x[1], x[2], x[3], d[0], d[1], d[2], d[3]);
}
double edge_edge(const Four& x, const Four& d) {
  return edge_edge_ccd(x[0], x[1], x[2], x[3], d[0], d[1], d[2], d[3]);
}

TEST(AdditiveCcd, GrazingAndParallelMotionsCompleteTheirStep) {
  const V zero = V::Zero();
  // Moving away, or both translating together (the pair moves rigidly): the whole step at once.
  EXPECT_EQ(point_triangle_ccd(V(0.2, 0.2, 0.1), ta, tb, tc, V(0, 0, 1), zero, zero, zero), 1.0);
  const V drift(5, -3, 2);
  EXPECT_EQ(point_triangle_ccd(V(0.2, 0.2, 1e-4), ta, tb, tc, drift, drift, drift, drift), 1.0);
  // Grazing 1 mm from the surface: CCD is conservative (it stops at 10% of the start
  // distance), so the step completes in a few calls, never touching on the way.
  const Four over{V(-1, 0.2, 1e-3), ta, tb, tc}, slide{V(3, 0, 0), zero, zero, zero};
  EXPECT_EQ(advance(over, slide, point_triangle, 20), 1.0);
  const Four along{V(-1, -1e-3, 0), ta, tb, tc};  // along the line of edge ab, 1 mm outside
  EXPECT_EQ(advance(along, slide, point_triangle, 20), 1.0);
  // Parallel edges sliding along each other 1 mm apart.
  const Four edges{V(0, 0, 0), V(1, 0, 0), V(-1, 0, 1e-3), V(0, 0, 1e-3)};
  EXPECT_EQ(advance(edges, {zero, zero, V(3, 0, 0), V(3, 0, 0)}, edge_edge, 20), 1.0);
  // A crossing, asked again and again, creeps towards the impact and never reaches it.
  const double crossing = advance({V(0.2, 0.2, 1), ta, tb, tc}, {V(0, 0, -2), zero, zero, zero}, point_triangle, 50);
  EXPECT_LT(crossing, 0.5);
  EXPECT_GT(crossing, 0.499);
}

TEST(AdditiveCcd, EdgesMeetingStopBeforeContact) {
  const V zero = V::Zero(), down(0, 0, -2);
  // Crossing edges, one 1 above the other, moving 2 towards it: contact at t = 0.5.
  const double crossing = edge_edge_ccd({-1, 0, 0}, {1, 0, 0}, {0, -1, 1}, {0, 1, 1}, zero, zero, down, down);
  EXPECT_LT(crossing, 0.5);
  EXPECT_GT(crossing, 0.4);
  // Parallel edges closing face to face: contact at t = 0.5.
  const double parallel = edge_edge_ccd({0, 0, 0}, {1, 0, 0}, {0, 0, 1}, {1, 0, 1}, zero, zero, down, down);
  EXPECT_LT(parallel, 0.5);
  EXPECT_GT(parallel, 0.4);
}

TEST(AdditiveCcd, NeverStepsPastAContactOnRandomTrajectories) {
  // Brute force: sample each trajectory finely. Where the pair comes within 0.5% of its start
  // distance (a crossing shows as such a sample), the CCD's time must lie before it: ACCD keeps
  // the pair apart by at least keep^2 = 1% of the start distance up to its time.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  auto random_point = [&] { return V(u(rng), u(rng), u(rng)); };
  int impacts = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Four x{random_point(), random_point(), random_point(), random_point()};
    Four dx{2 * random_point(), 2 * random_point(), 2 * random_point(), 2 * random_point()};
    for (const bool edges : {false, true}) {
      auto distance_at = [&](double t) {
        Four y;
        for (int i = 0; i < 4; ++i) y[i] = x[i] + t * dx[i];
        return edges ? edge_edge_distance(y[0], y[1], y[2], y[3]).distance
                     : point_triangle_distance(y[0], y[1], y[2], y[3]).distance;
      };
      const double t = edges ? edge_edge_ccd(x[0], x[1], x[2], x[3], dx[0], dx[1], dx[2], dx[3])
                             : point_triangle_ccd(x[0], x[1], x[2], x[3], dx[0], dx[1], dx[2], dx[3]);
      double first_contact = 2;
      double min_distance = distance_at(0);
      for (int k = 0; k <= 4000; ++k) {
        const double s = k / 4000.0;
        const double d = distance_at(s);
        if (s <= t) min_distance = std::min(min_distance, d);
        if (d < 0.005 * distance_at(0) && first_contact > 1) first_contact = s;
      }
      if (first_contact <= 1) {
        ++impacts;
        EXPECT_LT(t, first_contact) << "trial " << trial << (edges ? " edge-edge" : " point-triangle");
      }
      EXPECT_GT(min_distance, 0) << "trial " << trial;
      EXPECT_GT(distance_at(t), 0.05 * distance_at(0)) << "trial " << trial;
    }
  }
  EXPECT_GT(impacts, 0);  // the sample must contain impacts for the check to mean anything
}

}  // namespace
}  // namespace pb4u

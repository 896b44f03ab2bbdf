// Segments through a closed surface: crossing, entering and leaving (both ends outside), ending
// on a face, grazing and parallel segments on a box; and the KD-tree broad phase against every
// face of a sphere, with the closed form (a chord nearer the centre than the sphere's inscribed
// radius crosses it, one farther than its circumscribed radius does not).
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <random>

#include "pb4u/spatial/segments_through_surface.h"
#include "test_util.h"

namespace pb4u {
namespace {

// A UV sphere of radius r: `rings` latitude bands, `sides` longitudes, closed and outward.
TriMesh uv_sphere(double r, int rings, int sides) {
  TriMesh m;
  m.V.resize(2 + (rings - 1) * sides, 3);
  m.V.row(0) << 0, r, 0;
  m.V.row(1) << 0, -r, 0;
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < sides; ++j) {
      const double th = M_PI * i / rings, ph = 2 * M_PI * j / sides;
      m.V.row(2 + (i - 1) * sides + j) << r * std::sin(th) * std::cos(ph), r * std::cos(th), r * std::sin(th) * std::sin(ph);
    }
  auto at = [&](int i, int j) { return 2 + (i - 1) * sides + (j % sides); };
  std::vector<Eigen::RowVector3i> F;
  for (int j = 0; j < sides; ++j) {
    F.push_back({0, at(1, j + 1), at(1, j)});
    F.push_back({1, at(rings - 1, j), at(rings - 1, j + 1)});
    for (int i = 1; i + 1 < rings; ++i) {
      F.push_back({at(i, j), at(i, j + 1), at(i + 1, j)});
      F.push_back({at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)});
    }
  }
  m.F.resize(Eigen::Index(F.size()), 3);
  for (size_t f = 0; f < F.size(); ++f) m.F.row(Eigen::Index(f)) = F[f];
  return m;
}

TEST(SegmentsThroughSurface, ABoxIsCrossedByWhatEntersItOrPassesThroughAndNotByWhatGrazesIt) {
  const TriMesh box = test::box_mesh({0, 0, 0}, {1, 1, 1});
  Eigen::MatrixXd p(12, 3);
  p << 0.5, 0.5, -1, 0.5, 0.5, 0.5,  // 0: one end inside
      -1, 0.3, 0.6, 2, 0.4, 0.7,     // 1: both ends outside, in through one side and out of the other
      0.5, 0.5, -1, 0.5, 0.5, 0,     // 2: ends on a face
      2, 2, 2, 3, 3, 3,              // 3: far outside
      -0.5, 0.5, 1.1, 1.5, 0.5, 1.1, // 4: parallel to the top, above it
      0.5, 0.5, 1.1, 0.5, 0.5, 1.5;  // 5: above the top, pointing away
  Eigen::MatrixXi s(6, 2);
  for (int k = 0; k < 6; ++k) s.row(k) << 2 * k, 2 * k + 1;
  EXPECT_EQ(segments_through_surface(p, s, box.V, box.F), (std::vector<int>{0, 1, 2}));
}

TEST(SegmentsThroughSurface, TheBroadPhaseFindsWhatEveryFaceFindsOnASphere) {
  const double R = 0.3;
  const int sides = 24, rings = 12;
  const TriMesh sphere = uv_sphere(R, rings, sides);
  // Every point of the polygon surface lies between these radii of the centre.
  const double inscribed = R * std::cos(M_PI / rings) * std::cos(M_PI / sides);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  const int k = 400;
  Eigen::MatrixXd p(2 * k, 3);
  Eigen::MatrixXi s(k, 2);
  for (int i = 0; i < k; ++i) {
    // Chords of random direction at random distances from the centre, ends 0.5 m apart or less.
    Eigen::Vector3d d(u(rng), u(rng), u(rng)), a(u(rng), u(rng), u(rng));
    d.normalize();
    const Eigen::Vector3d foot = (a - a.dot(d) * d).normalized() * (0.5 * R * (1 + u(rng)) + 0.2 * R);
    const double half = 0.25 * (1.5 + u(rng));
    p.row(2 * i) = (foot - half * d).transpose();
    p.row(2 * i + 1) = (foot + half * d).transpose();
    s.row(i) << 2 * i, 2 * i + 1;
  }
  const std::vector<int> found = segments_through_surface(p, s, sphere.V, sphere.F);
  std::vector<int> every_face;
  int closed_form_through = 0, closed_form_clear = 0;
  for (int i = 0; i < k; ++i) {
    const Eigen::Vector3d a = p.row(2 * i).transpose(), b = p.row(2 * i + 1).transpose();
    bool hit = false;
    for (Eigen::Index f = 0; f < sphere.F.rows(); ++f)
      hit = hit || segment_crosses_triangle(a, b, sphere.V.row(sphere.F(f, 0)).transpose(),
                                            sphere.V.row(sphere.F(f, 1)).transpose(),
                                            sphere.V.row(sphere.F(f, 2)).transpose());
    if (hit) every_face.push_back(i);
    // The closed form where it decides: the line's distance to the centre, both ends outside.
    const Eigen::Vector3d dir = (b - a).normalized();
    const double line = (a - a.dot(dir) * dir).norm();
    if (a.norm() > R && b.norm() > R && a.dot(dir) < 0 && b.dot(dir) > 0 && line < inscribed - 1e-6) {
      EXPECT_TRUE(hit) << "segment " << i << " passes " << line << " m from the centre";
      ++closed_form_through;
    }
    if (line > R + 1e-6) {
      EXPECT_FALSE(hit) << "segment " << i << " passes " << line << " m from the centre";
      ++closed_form_clear;
    }
  }
  EXPECT_EQ(found, every_face);
  EXPECT_GT(closed_form_through, 50);  // the sample decides both ways, often
  EXPECT_GT(closed_form_clear, 50);
}

}  // namespace
}  // namespace pb4u

#pragma once
// Continuous collision detection by additive CCD (Li, Kaufman and Kim 2021, "Codimensional
// Incremental Potential Contact", Algorithm 1): four points move linearly from x to x + t dx;
// the result is a time of impact t in [0, t_max] before which the pair stays apart. It
// advances t by steps that provably cannot close the remaining distance (the distance divided
// by an upper bound on how fast it can shrink) and stops once the distance has fallen to a
// fraction `keep` of where it started: the pair is then still `keep` x its start distance
// apart, never touching, however the points move. No root finding, no tolerance on a
// polynomial: what a line search needs to never step through a surface.
#include <Eigen/Core>

namespace pb4u {

struct AdditiveCcdOptions {
  double keep = 0.1;       // stop at keep x the start distance (ACCD's s)
  double t_max = 1;        // the step's length: no impact before it means t_max
  int max_iterations = 10000;  // a cap on the advance loop; reached, it returns the t so far
  double touching = 1e-12;     // m: a distance this small counts as contact (rounding
                               // cannot tell which side of a surface such a point is on)
};

// Vertex p (moving by dp) against triangle (a, b, c) (moving by da, db, dc): the largest safe
// fraction of the step, t_max when they never come within keep x their start distance. 0 when
// they touch at the start. A pair that does not collide may still get t < t_max (it came
// within keep x its start distance): a line search steps there and asks again from closer.
double point_triangle_ccd(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                          const Eigen::Vector3d& c, const Eigen::Vector3d& dp, const Eigen::Vector3d& da,
                          const Eigen::Vector3d& db, const Eigen::Vector3d& dc,
                          const AdditiveCcdOptions& options = {});

// Segment (a0, a1) against segment (b0, b1), likewise.
double edge_edge_ccd(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b0,
                     const Eigen::Vector3d& b1, const Eigen::Vector3d& da0, const Eigen::Vector3d& da1,
                     const Eigen::Vector3d& db0, const Eigen::Vector3d& db1,
                     const AdditiveCcdOptions& options = {});

}  // namespace pb4u

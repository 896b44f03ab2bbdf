#include "pb4u/physics/primitive_distance.h"

#include <algorithm>
#include <cmath>

#include "pb4u/mesh/closest_point_on_triangle.h"

namespace pb4u {
namespace {

// distance and gradient from the closest-point difference r = sum_i w_i x_i.
PrimitiveDistance from_difference(const Eigen::Vector3d& r, const Eigen::Vector4d& w) {
  PrimitiveDistance out;
  out.distance = r.norm();
  out.weights = w;
  out.gradient.setZero();
  if (out.distance > 0) {
    const Eigen::Vector3d u = r / out.distance;
    for (int i = 0; i < 4; ++i) out.gradient.segment<3>(3 * i) = w(i) * u;
  }
  return out;
}

}  // namespace

PrimitiveDistance point_triangle_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const ClosestPointOnTriangle q = closest_point_on_triangle(p, a, b, c);
  return from_difference(p - q.point, Eigen::Vector4d(1, -q.weights(0), -q.weights(1), -q.weights(2)));
}

PrimitiveDistance edge_edge_distance(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1,
                                     const Eigen::Vector3d& b0, const Eigen::Vector3d& b1) {
  // Ericson, Real-Time Collision Detection, 5.1.9: closest points a0 + s da, b0 + t db.
  const Eigen::Vector3d da = a1 - a0, db = b1 - b0, r0 = a0 - b0;
  const double A = da.squaredNorm(), E = db.squaredNorm(), f = db.dot(r0);
  const double tiny = 1e-30;
  double s = 0, t = 0;
  if (A <= tiny && E <= tiny) {
    s = t = 0;
  } else if (A <= tiny) {
    t = std::clamp(f / E, 0.0, 1.0);
  } else {
    const double c = da.dot(r0);
    if (E <= tiny) {
      s = std::clamp(-c / A, 0.0, 1.0);
    } else {
      const double b = da.dot(db), denom = A * E - b * b;
      // Parallel (denom ~ 0): any s works; take 0 and let t follow.
      s = denom > 1e-14 * A * E ? std::clamp((b * f - c * E) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / E;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / A, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / A, 0.0, 1.0);
      }
    }
  }
  const Eigen::Vector3d r = (a0 + s * da) - (b0 + t * db);
  return from_difference(r, Eigen::Vector4d(1 - s, s, -(1 - t), -t));
}

}  // namespace pb4u

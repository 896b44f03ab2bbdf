#pragma once
// How many times a closed, outward-oriented triangle surface wraps each point: 0 outside, 1
// inside, 2 where two parts of a surface that crosses itself overlap (a forearm swung into the
// torso). Counted along a ray in +x: +1 for each face the ray leaves through (normal with
// positive x), -1 for each it enters through. The faces are binned once on a grid over their
// (y, z) extent, so a query tests only the faces of its column. The ray starts from the point
// moved by 1e-9 m in y and z (an irrational-ratio nudge), so that it misses edges and corners
// exactly on its line, which a float mesh puts there often (axis-aligned boxes).
#include <Eigen/Core>

#include <memory>

namespace pb4u {

class WindingNumbers {
 public:
  // V: nb x 3 (m), F: mb x 3 outward faces of a closed surface. Throws pb4u::Error on an empty
  // surface, a non-finite vertex or an out-of-range face index.
  WindingNumbers(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);
  ~WindingNumbers();
  WindingNumbers(WindingNumbers&&) noexcept;
  WindingNumbers& operator=(WindingNumbers&&) noexcept;

  // points: n x 3 (m). Returns n winding numbers.
  Eigen::VectorXi at(const Eigen::MatrixXd& points) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pb4u

#include "pb4u/body/outer_faces.h"

#include <Eigen/Geometry>

#include "pb4u/spatial/winding_number.h"

namespace pb4u {

std::vector<char> covered_faces(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const WindingNumbers* wraps) {
  constexpr double kOffset = 1e-4;  // m outside the centroid
  Eigen::MatrixXd probes(F.rows(), 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::RowVector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const Eigen::RowVector3d n = (b - a).cross(c - a);
    const double length = n.norm();
    probes.row(f) = (a + b + c) / 3.0 + (length > 0 ? kOffset / length : 0.0) * n;
  }
  const Eigen::VectorXi w = wraps ? wraps->at(probes) : WindingNumbers(V, F).at(probes);
  std::vector<char> covered(size_t(F.rows()));
  for (Eigen::Index f = 0; f < F.rows(); ++f) covered[size_t(f)] = w(f) >= 1;
  return covered;
}

Eigen::MatrixXi outer_faces(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const WindingNumbers* wraps) {
  return outer_faces(F, covered_faces(V, F, wraps));
}

Eigen::MatrixXi outer_faces(const Eigen::MatrixXi& F, const std::vector<char>& covered) {
  std::vector<int> keep;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    if (!covered[size_t(f)]) keep.push_back(int(f));
  if (Eigen::Index(keep.size()) == F.rows()) return F;
  Eigen::MatrixXi out(Eigen::Index(keep.size()), 3);
  for (size_t r = 0; r < keep.size(); ++r) out.row(Eigen::Index(r)) = F.row(keep[r]);
  return out;
}

}  // namespace pb4u

#include "pb4u/scene/pins.h"

namespace pb4u {

std::vector<int> top_band_vertices(const Eigen::MatrixXd& x, double top_band) {
  std::vector<int> pinned;
  if (x.rows() == 0) return pinned;
  const double top = x.col(1).maxCoeff();
  for (int i = 0; i < x.rows(); ++i)
    if (x(i, 1) >= top - top_band) pinned.push_back(i);
  return pinned;
}

}  // namespace pb4u

#include "pb4u/spatial/box_grid.h"

#include <algorithm>
#include <cmath>

namespace pb4u {

namespace {
// The cell of point p along each axis, clamped to the grid.
Eigen::Array3i cell_of(const Eigen::Array3d& p, const Eigen::Array3d& origin, double cell, const Eigen::Array3i& dims) {
  Eigen::Array3i c;
  for (int k = 0; k < 3; ++k)
    c[k] = std::clamp(static_cast<int>(std::floor((p[k] - origin[k]) / cell)), 0, dims[k] - 1);
  return c;
}
}  // namespace

BoxGrid::BoxGrid(const Eigen::MatrixXd& lo, const Eigen::MatrixXd& hi) : n_(static_cast<int>(lo.rows())) {
  if (n_ == 0) return;
  origin_ = lo.colwise().minCoeff().transpose().array();
  top_ = hi.colwise().maxCoeff().transpose().array();
  const Eigen::Array3d extent = top_ - origin_;
  double side = (hi - lo).rowwise().maxCoeff().mean();
  // A set of points (or boxes all smaller than their spread allows): a cell that holds a few.
  cell_ = std::max({side, 1e-3 * extent.maxCoeff(), 1e-9});
  auto dims_at = [&](double cell) { return (extent / cell).floor().cast<int>() + 1; };
  dims_ = dims_at(cell_);
  while (double(dims_[0]) * dims_[1] * dims_[2] > 8.0 * n_ + 64) dims_ = dims_at(cell_ *= 1.5);

  // Counting sort of (cell, box) by cell; each cell's boxes stay ascending.
  const size_t cells = size_t(dims_[0]) * dims_[1] * dims_[2];
  start_.assign(cells + 1, 0);
  auto for_each_cell = [&](int i, auto&& f) {
    const Eigen::Array3i a = cell_of(lo.row(i).transpose().array(), origin_, cell_, dims_);
    const Eigen::Array3i b = cell_of(hi.row(i).transpose().array(), origin_, cell_, dims_);
    for (int x = a[0]; x <= b[0]; ++x)
      for (int y = a[1]; y <= b[1]; ++y)
        for (int z = a[2]; z <= b[2]; ++z) f((size_t(x) * dims_[1] + y) * dims_[2] + z);
  };
  for (int i = 0; i < n_; ++i) for_each_cell(i, [&](size_t c) { ++start_[c + 1]; });
  for (size_t c = 0; c < cells; ++c) start_[c + 1] += start_[c];
  ids_.resize(size_t(start_[cells]));
  std::vector<int> fill(start_.begin(), start_.end() - 1);
  for (int i = 0; i < n_; ++i) for_each_cell(i, [&](size_t c) { ids_[size_t(fill[c]++)] = i; });
}

void BoxGrid::near_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, std::vector<int>* out) const {
  out->clear();
  // A query that is not finite (a diverged state) meets nothing, as a KD-tree's distances would.
  if (n_ == 0 || !lo.allFinite() || !hi.allFinite() || (hi.array() < origin_).any() || (lo.array() > top_).any()) return;
  const Eigen::Array3i a = cell_of(lo.array(), origin_, cell_, dims_);
  const Eigen::Array3i b = cell_of(hi.array(), origin_, cell_, dims_);
  for (int x = a[0]; x <= b[0]; ++x)
    for (int y = a[1]; y <= b[1]; ++y)
      for (int z = a[2]; z <= b[2]; ++z) {
        const size_t c = (size_t(x) * dims_[1] + y) * dims_[2] + z;
        out->insert(out->end(), ids_.begin() + start_[c], ids_.begin() + start_[c + 1]);
      }
  std::sort(out->begin(), out->end());
  out->erase(std::unique(out->begin(), out->end()), out->end());
}

}  // namespace pb4u

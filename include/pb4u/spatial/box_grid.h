#pragma once
// Axis-aligned boxes binned in a uniform grid: which of them may overlap a query box. Built in
// O(n) and queried in time proportional to the cells the query covers, whatever the boxes'
// sizes elsewhere: the broad phase of contact (physics/contact_candidates.h), where a KD-tree
// over centres must grow every query by the largest box of the set.
#include <Eigen/Core>

#include <vector>

namespace pb4u {

class BoxGrid {
 public:
  BoxGrid() = default;
  // lo, hi: n x 3 box corners (lo <= hi). The cell is the boxes' mean largest side, grown where
  // the grid would have more than about 8 cells per box.
  BoxGrid(const Eigen::MatrixXd& lo, const Eigen::MatrixXd& hi);

  int size() const { return n_; }
  double cell() const { return cell_; }

  // Every box whose cells meet [lo, hi], ascending, without repeats: all boxes that overlap it
  // and some near it (the caller tests the pairs it keeps). *out is overwritten.
  void near_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, std::vector<int>* out) const;

 private:
  int n_ = 0;
  double cell_ = 1;
  Eigen::Array3d origin_ = Eigen::Array3d::Zero(), top_ = Eigen::Array3d::Zero();  // the boxes' bounds
  Eigen::Array3i dims_ = Eigen::Array3i::Zero();
  std::vector<int> start_;  // per cell (x-major), where its boxes begin in ids_; one past the end last
  std::vector<int> ids_;
};

}  // namespace pb4u

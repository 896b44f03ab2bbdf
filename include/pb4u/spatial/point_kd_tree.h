#pragma once
// Nearest-neighbour and radius queries over a fixed point set (nanoflann KD-tree,
// O(n log n) build, O(log n) per query). Used for body queries (nearest body face by
// centroid, nearest body vertex), world edges and skinning-weight transfer.
#include <Eigen/Core>
#include <memory>
#include <utility>
#include <vector>

namespace pb4u {

class PointKdTree {
 public:
  // points: n x 3 (copied). An empty set is allowed; queries then return -1 / nothing.
  explicit PointKdTree(const Eigen::MatrixXd& points);
  ~PointKdTree();
  PointKdTree(PointKdTree&&) noexcept;
  PointKdTree& operator=(PointKdTree&&) noexcept;

  int size() const;

  // For each query row, the index of the nearest point (-1 if empty) and its squared distance.
  void nearest(const Eigen::MatrixXd& queries, Eigen::VectorXi* index,
               Eigen::VectorXd* squared_distance = nullptr) const;

  // All (query row, point index) pairs closer than `radius` (m), sorted by query then point.
  std::vector<std::pair<int, int>> within_radius(const Eigen::MatrixXd& queries, double radius) const;

  // The points closer than `radius` (m) to one query point, sorted: for per-query radii.
  std::vector<int> within_radius_of(const Eigen::Vector3d& query, double radius) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pb4u

#include "pb4u/spatial/point_kd_tree.h"

#include <nanoflann.hpp>

#include <algorithm>

namespace pb4u {

namespace {
// nanoflann dataset adaptor over an owned row-major point list.
struct PointCloud {
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> P;
  size_t kdtree_get_point_count() const { return static_cast<size_t>(P.rows()); }
  double kdtree_get_pt(size_t i, size_t d) const { return P(static_cast<Eigen::Index>(i), d); }
  template <class BBox>
  bool kdtree_get_bbox(BBox&) const { return false; }
};
using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointCloud>,
                                                 PointCloud, 3, size_t>;

// The (index, squared distance) pairs strictly closer than `radius` to p, sorted by index.
void sorted_hits_within(const Tree& tree, const double p[3], double radius,
                        std::vector<std::pair<size_t, double>>* hits) {
  nanoflann::SearchParams params;
  params.sorted = false;
  hits->clear();
  // nanoflann's L2 adaptors take the squared radius (and keep distances equal to it).
  tree.radiusSearch(p, radius * radius, *hits, params);
  hits->erase(std::remove_if(hits->begin(), hits->end(),
                             [&](const std::pair<size_t, double>& h) { return !(h.second < radius * radius); }),
              hits->end());
  std::sort(hits->begin(), hits->end());
}
}  // namespace

struct PointKdTree::Impl {
  PointCloud cloud;
  std::unique_ptr<Tree> tree;
};

PointKdTree::PointKdTree(const Eigen::MatrixXd& points) : impl_(std::make_unique<Impl>()) {
  impl_->cloud.P = points;
  if (points.rows() > 0) {
    impl_->tree = std::make_unique<Tree>(3, impl_->cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    impl_->tree->buildIndex();
  }
}

PointKdTree::~PointKdTree() = default;
PointKdTree::PointKdTree(PointKdTree&&) noexcept = default;
PointKdTree& PointKdTree::operator=(PointKdTree&&) noexcept = default;

int PointKdTree::size() const { return static_cast<int>(impl_->cloud.P.rows()); }

void PointKdTree::nearest(const Eigen::MatrixXd& queries, Eigen::VectorXi* index,
                          Eigen::VectorXd* squared_distance) const {
  const Eigen::Index n = queries.rows();
  index->resize(n);
  if (squared_distance) squared_distance->resize(n);
  for (Eigen::Index q = 0; q < n; ++q) {
    size_t best = 0;
    double d2 = 0;
    double p[3] = {queries(q, 0), queries(q, 1), queries(q, 2)};
    if (impl_->tree && impl_->tree->knnSearch(p, 1, &best, &d2) == 1) {
      (*index)(q) = static_cast<int>(best);
    } else {
      (*index)(q) = -1;
      d2 = std::numeric_limits<double>::infinity();
    }
    if (squared_distance) (*squared_distance)(q) = d2;
  }
}

std::vector<std::pair<int, int>> PointKdTree::within_radius(const Eigen::MatrixXd& queries,
                                                            double radius) const {
  std::vector<std::pair<int, int>> pairs;
  if (!impl_->tree) return pairs;
  std::vector<std::pair<size_t, double>> hits;
  for (Eigen::Index q = 0; q < queries.rows(); ++q) {
    const double p[3] = {queries(q, 0), queries(q, 1), queries(q, 2)};
    sorted_hits_within(*impl_->tree, p, radius, &hits);
    for (const auto& h : hits) pairs.emplace_back(static_cast<int>(q), static_cast<int>(h.first));
  }
  return pairs;
}

std::vector<int> PointKdTree::within_radius_of(const Eigen::Vector3d& query, double radius) const {
  std::vector<int> out;
  if (!impl_->tree) return out;
  std::vector<std::pair<size_t, double>> hits;
  const double p[3] = {query.x(), query.y(), query.z()};
  sorted_hits_within(*impl_->tree, p, radius, &hits);
  for (const auto& h : hits) out.push_back(static_cast<int>(h.first));
  return out;
}

}  // namespace pb4u

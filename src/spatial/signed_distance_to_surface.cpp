#include "pb4u/spatial/signed_distance_to_surface.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "pb4u/mesh/closest_point_on_triangle.h"
#include "pb4u/spatial/point_kd_tree.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace {

// Per-surface data for the queries: unit face normals (zero for zero-area faces), the
// pseudo-normals of corners (angle-weighted) and edges (sum of the incident face normals).
struct Surface {
  const Eigen::MatrixXd& V;
  const Eigen::MatrixXi& F;
  Eigen::MatrixXd face_normal, vertex_normal;
  std::unordered_map<int64_t, Eigen::Vector3d> edge_normal;  // key: edge_key(i, j)
  std::vector<int> faces;                                    // the faces of positive area
  double max_face_radius = 0;                                // m: centroid to farthest corner

  Surface(const Eigen::MatrixXd& V_, const Eigen::MatrixXi& F_) : V(V_), F(F_) {}

  int64_t edge_key(int i, int j) const {
    return int64_t(std::min(i, j)) * int64_t(V.rows()) + int64_t(std::max(i, j));
  }
  Eigen::Vector3d corner(int f, int k) const { return V.row(F(f, k)).transpose(); }
};

Surface build_surface(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Surface s(V, F);
  s.face_normal = Eigen::MatrixXd::Zero(F.rows(), 3);
  s.vertex_normal = Eigen::MatrixXd::Zero(V.rows(), 3);
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = s.corner(f, 0), b = s.corner(f, 1), c = s.corner(f, 2);
    const Eigen::Vector3d cross = (b - a).cross(c - a);
    const double norm = cross.norm();
    if (!(norm > 0)) continue;
    const Eigen::Vector3d n = cross / norm;
    s.face_normal.row(f) = n.transpose();
    s.faces.push_back(f);
    const Eigen::Vector3d centroid = (a + b + c) / 3.0;
    s.max_face_radius = std::max({s.max_face_radius, (a - centroid).norm(), (b - centroid).norm(),
                                  (c - centroid).norm()});
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d p = s.corner(f, k), e1 = s.corner(f, (k + 1) % 3) - p,
                            e2 = s.corner(f, (k + 2) % 3) - p;
      const double angle = std::atan2(e1.cross(e2).norm(), e1.dot(e2));
      s.vertex_normal.row(F(f, k)) += angle * n.transpose();
      // Eigen vectors start uninitialised: a new edge starts at zero explicitly.
      s.edge_normal.try_emplace(s.edge_key(F(f, k), F(f, (k + 1) % 3)), Eigen::Vector3d::Zero()).first->second += n;
    }
  }
  return s;
}

// The pseudo-normal of the feature of face f that the closest point lies on.
Eigen::Vector3d pseudo_normal(const Surface& s, int f, TriangleFeature feature) {
  auto edge = [&](int k) -> Eigen::Vector3d { return s.edge_normal.at(s.edge_key(s.F(f, k), s.F(f, (k + 1) % 3))); };
  switch (feature) {
    case TriangleFeature::interior: return s.face_normal.row(f).transpose();
    case TriangleFeature::edge_ab: return edge(0);
    case TriangleFeature::edge_bc: return edge(1);
    case TriangleFeature::edge_ca: return edge(2);
    case TriangleFeature::corner_a: return s.vertex_normal.row(s.F(f, 0)).transpose();
    case TriangleFeature::corner_b: return s.vertex_normal.row(s.F(f, 1)).transpose();
    case TriangleFeature::corner_c: return s.vertex_normal.row(s.F(f, 2)).transpose();
  }
  return Eigen::Vector3d::Zero();
}

}  // namespace

struct SurfaceQuery::Impl {
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  Surface surface;  // refers to V and F above: an Impl is never moved (held by unique_ptr)
  std::unique_ptr<PointKdTree> tree;

  Impl(const Eigen::MatrixXd& V_, const Eigen::MatrixXi& F_) : V(V_), F(F_), surface(build_surface(V, F)) {
    if (surface.faces.empty()) throw Error("signed distance: the surface has no face of positive area");
    Eigen::MatrixXd centroids(surface.faces.size(), 3);
    for (size_t i = 0; i < surface.faces.size(); ++i) {
      const int f = surface.faces[i];
      centroids.row(i) = ((surface.corner(f, 0) + surface.corner(f, 1) + surface.corner(f, 2)) / 3.0).transpose();
    }
    tree = std::make_unique<PointKdTree>(centroids);
  }
};

SurfaceQuery::SurfaceQuery(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  if (V.cols() != 3 || F.cols() != 3) throw Error("signed distance: surface vertices and faces must have 3 columns");
  if (!V.allFinite()) throw Error("signed distance: the surface vertices are not finite");
  if (F.rows() > 0 && (F.minCoeff() < 0 || F.maxCoeff() >= V.rows()))
    throw Error("signed distance: a surface face index is out of range");
  impl_ = std::make_unique<Impl>(V, F);
}
SurfaceQuery::~SurfaceQuery() = default;
SurfaceQuery::SurfaceQuery(SurfaceQuery&&) noexcept = default;
SurfaceQuery& SurfaceQuery::operator=(SurfaceQuery&&) noexcept = default;

SurfaceProjection SurfaceQuery::project(const Eigen::MatrixXd& points) const {
  if (points.cols() != 3) throw Error("signed distance: points, surface vertices and faces must have 3 columns");
  if (!points.allFinite()) throw Error("signed distance: the points are not finite");
  const Surface& s = impl_->surface;
  const PointKdTree& tree = *impl_->tree;
  Eigen::VectorXi nearest;
  tree.nearest(points, &nearest);

  SurfaceProjection out;
  out.distance.resize(points.rows());
  out.closest.resize(points.rows(), 3);
  out.outward.resize(points.rows(), 3);
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    const Eigen::Vector3d p = points.row(i).transpose();
    auto closest_on = [&](int f) { return closest_point_on_triangle(p, s.corner(f, 0), s.corner(f, 1), s.corner(f, 2)); };
    int best_face = s.faces[nearest(i)];
    ClosestPointOnTriangle best = closest_on(best_face);
    double best_d2 = (p - best.point).squaredNorm();
    // Slightly widened so a face whose centroid is exactly at the bound is not lost to rounding.
    const double radius = (std::sqrt(best_d2) + s.max_face_radius) * (1 + 1e-9) + 1e-12;
    for (int c : tree.within_radius_of(p, radius)) {
      const int f = s.faces[c];
      const ClosestPointOnTriangle q = closest_on(f);
      const double d2 = (p - q.point).squaredNorm();
      if (d2 < best_d2) best_d2 = d2, best = q, best_face = f;
    }
    const double d = std::sqrt(best_d2);
    const Eigen::Vector3d normal = pseudo_normal(s, best_face, best.feature);
    const bool inside = (p - best.point).dot(normal) < 0;
    out.distance(i) = inside ? -d : d;
    out.closest.row(i) = best.point.transpose();
    Eigen::Vector3d outward = normal.normalized();  // on the surface
    if (d > 1e-12 * (1 + p.norm())) outward = (inside ? -1.0 : 1.0) * (p - best.point) / d;
    out.outward.row(i) = outward.transpose();
  }
  return out;
}

SurfaceProjection project_onto_surface(const Eigen::MatrixXd& points, const Eigen::MatrixXd& V,
                                       const Eigen::MatrixXi& F) {
  if (points.cols() != 3) throw Error("signed distance: points, surface vertices and faces must have 3 columns");
  if (!points.allFinite()) throw Error("signed distance: the points are not finite");
  return SurfaceQuery(V, F).project(points);
}

Eigen::VectorXd signed_distance_to_surface(const Eigen::MatrixXd& points, const Eigen::MatrixXd& V,
                                           const Eigen::MatrixXi& F) {
  return project_onto_surface(points, V, F).distance;
}

}  // namespace pb4u

#include "pb4u/physics/contact_candidates.h"

#include <algorithm>

#include "pb4u/mesh/edges.h"
#include "pb4u/spatial/box_grid.h"

namespace pb4u {
namespace {

// An axis-aligned box around points and where they move to.
struct Box {
  Eigen::Array3d lo = Eigen::Array3d::Constant(1e300), hi = Eigen::Array3d::Constant(-1e300);
  void add(const Eigen::MatrixXd& X, const Eigen::MatrixXd& D, int i) {
    const Eigen::Array3d p = X.row(i).transpose().array();
    lo = lo.min(p);
    hi = hi.max(p);
    if (D.rows()) {
      const Eigen::Array3d q = p + D.row(i).transpose().array();
      lo = lo.min(q);
      hi = hi.max(q);
    }
  }
  // Whether the boxes come within `gap` of each other.
  bool near(const Box& o, double gap) const {
    return ((lo - gap) <= o.hi).all() && ((hi + gap) >= o.lo).all();
  }
};

// Largest row norm of M (0 for an empty M).
double largest_row_norm(const Eigen::MatrixXd& M) {
  return M.rows() ? M.rowwise().norm().maxCoeff() : 0.0;
}

}  // namespace

// Grids over a surface's face and edge boxes at positions V (spatial/box_grid.h), with the face
// centroids and edge midpoints and the largest distance from a centroid to its face's corners
// and from a midpoint to its edge's ends.
struct SurfaceIndex {
  Eigen::MatrixXd V, centroid, midpoint;
  BoxGrid faces, edges;
  double face_reach = 0, edge_half = 0;
};

namespace {

// The surface's index at its current V: the cached one, or built anew.
const SurfaceIndex& surface_index(const ContactSurface& body) {
  if (body.index && body.index->V.rows() == body.V.rows() && body.index->V == body.V) return *body.index;
  const Eigen::Index mb = body.F.rows(), eb = body.E.rows();
  auto index = std::make_shared<SurfaceIndex>();
  index->V = body.V;
  // A point within r of a face is within r + (the face's circumradius about its centroid) of
  // the centroid; likewise for edges and midpoints.
  index->centroid.resize(mb, 3);
  Eigen::MatrixXd lo(mb, 3), hi(mb, 3);
  for (Eigen::Index f = 0; f < mb; ++f) {
    const auto a = body.V.row(body.F(f, 0)), b = body.V.row(body.F(f, 1)), c = body.V.row(body.F(f, 2));
    index->centroid.row(f) = (a + b + c) / 3;
    lo.row(f) = a.cwiseMin(b).cwiseMin(c);
    hi.row(f) = a.cwiseMax(b).cwiseMax(c);
    for (int k = 0; k < 3; ++k)
      index->face_reach = std::max(index->face_reach, (body.V.row(body.F(f, k)) - index->centroid.row(f)).norm());
  }
  index->faces = BoxGrid(lo, hi);
  index->midpoint.resize(eb, 3);
  lo.resize(eb, 3);
  hi.resize(eb, 3);
  for (Eigen::Index e = 0; e < eb; ++e) {
    const auto a = body.V.row(body.E(e, 0)), b = body.V.row(body.E(e, 1));
    index->midpoint.row(e) = (a + b) / 2;
    lo.row(e) = a.cwiseMin(b);
    hi.row(e) = a.cwiseMax(b);
    index->edge_half = std::max(index->edge_half, (a - index->midpoint.row(e)).norm());
  }
  index->edges = BoxGrid(lo, hi);
  body.index = std::move(index);
  return *body.index;
}

}  // namespace

ContactSurface make_contact_surface(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  return {V, F, unique_edges(F), nullptr};  // the index is built at the first query
}

ContactCandidates contact_candidates(const Eigen::MatrixXd& x, const Eigen::MatrixXd& dx,
                                     const Eigen::MatrixXi& cloth_edges, const ContactSurface& body,
                                     const Eigen::MatrixXd& body_motion, double distance) {
  ContactCandidates out;
  const Eigen::Index mb = body.F.rows(), eb = body.E.rows();
  if (mb == 0 || x.rows() == 0) return out;
  const double body_step = largest_row_norm(body_motion);
  const Eigen::VectorXd step = dx.rows() ? Eigen::VectorXd(dx.rowwise().norm()) : Eigen::VectorXd::Zero(x.rows());
  const SurfaceIndex& index = surface_index(body);
  const double face_reach = index.face_reach;
  // Within r of the centroid, as a KD-tree over the centroids would be asked (squared, strict).
  auto within = [](const Eigen::MatrixXd& points, int p, const Eigen::Vector3d& q, double r) {
    const double d0 = q[0] - points(p, 0), d1 = q[1] - points(p, 1), d2 = q[2] - points(p, 2);
    return d0 * d0 + d1 * d1 + d2 * d2 < r * r;
  };

  // The grid's cells are a first cut; the centroid's reach and boxes around each primitive's
  // sweep keep only the pairs that can really come within `distance`.
  std::vector<Box> face_box(static_cast<size_t>(mb));
  for (Eigen::Index f = 0; f < mb; ++f)
    for (int k = 0; k < 3; ++k) face_box[size_t(f)].add(body.V, body_motion, body.F(f, k));
  std::vector<int> near;
  const double grow = distance + body_step;  // a face's sweep lies within its box grown by body_step
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    Box vertex;
    vertex.add(x, dx, int(i));
    index.faces.near_box((vertex.lo - grow).matrix(), (vertex.hi + grow).matrix(), &near);
    const Eigen::Vector3d p = x.row(i).transpose();
    const double reach = distance + step(i) + body_step + face_reach;
    for (int f : near)
      if (within(index.centroid, f, p, reach) && vertex.near(face_box[size_t(f)], distance))
        out.vertex_face.push_back({int(i), f});
  }

  if (eb == 0 || cloth_edges.rows() == 0) return out;
  const double body_half = index.edge_half;
  std::vector<Box> edge_box(static_cast<size_t>(eb));
  for (Eigen::Index e = 0; e < eb; ++e)
    for (int k = 0; k < 2; ++k) edge_box[size_t(e)].add(body.V, body_motion, body.E(e, k));
  for (Eigen::Index e = 0; e < cloth_edges.rows(); ++e) {
    const int a = cloth_edges(e, 0), b = cloth_edges(e, 1);
    const Eigen::Vector3d mid = (x.row(a) + x.row(b)).transpose() / 2;
    const double half = (x.row(a) - x.row(b)).norm() / 2, moved = std::max(step(a), step(b));
    Box cloth_box;
    cloth_box.add(x, dx, a);
    cloth_box.add(x, dx, b);
    index.edges.near_box((cloth_box.lo - grow).matrix(), (cloth_box.hi + grow).matrix(), &near);
    const double reach = distance + moved + body_step + half + body_half;
    for (int be : near)
      if (within(index.midpoint, be, mid, reach) && cloth_box.near(edge_box[size_t(be)], distance))
        out.edge_edge.push_back({int(e), be});
  }
  return out;
}

void drop_pairs_of(const std::vector<char>& excluded, const Eigen::MatrixXi& cloth_edges,
                   ContactCandidates* candidates) {
  if (std::find(excluded.begin(), excluded.end(), 1) == excluded.end()) return;
  auto& vf = candidates->vertex_face;
  vf.erase(std::remove_if(vf.begin(), vf.end(), [&](const std::array<int, 2>& p) { return excluded[size_t(p[0])]; }),
           vf.end());
  auto& ee = candidates->edge_edge;
  ee.erase(std::remove_if(ee.begin(), ee.end(),
                          [&](const std::array<int, 2>& p) {
                            return excluded[size_t(cloth_edges(p[0], 0))] || excluded[size_t(cloth_edges(p[0], 1))];
                          }),
           ee.end());
}

}  // namespace pb4u

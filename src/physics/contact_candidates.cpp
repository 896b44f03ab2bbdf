#include "pb4u/physics/contact_candidates.h"

#include <algorithm>

#include "pb4u/mesh/edges.h"
#include "pb4u/spatial/point_kd_tree.h"

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

// KD-trees over a surface's face centroids and edge midpoints at positions V, with the largest
// distance from a centroid to its face's corners and from a midpoint to its edge's ends.
struct SurfaceIndex {
  Eigen::MatrixXd V;
  PointKdTree faces, edges;
  double face_reach = 0, edge_half = 0;
  SurfaceIndex(const Eigen::MatrixXd& V, PointKdTree faces, PointKdTree edges, double face_reach, double edge_half)
      : V(V), faces(std::move(faces)), edges(std::move(edges)), face_reach(face_reach), edge_half(edge_half) {}
};

namespace {

// The surface's index at its current V: the cached one, or built anew.
const SurfaceIndex& surface_index(const ContactSurface& body) {
  if (body.index && body.index->V.rows() == body.V.rows() && body.index->V == body.V) return *body.index;
  const Eigen::Index mb = body.F.rows(), eb = body.E.rows();
  // A point within r of a face is within r + (the face's circumradius about its centroid) of
  // the centroid; likewise for edges and midpoints.
  Eigen::MatrixXd centroid(mb, 3);
  double face_reach = 0;
  for (Eigen::Index f = 0; f < mb; ++f) {
    centroid.row(f) = (body.V.row(body.F(f, 0)) + body.V.row(body.F(f, 1)) + body.V.row(body.F(f, 2))) / 3;
    for (int k = 0; k < 3; ++k) face_reach = std::max(face_reach, (body.V.row(body.F(f, k)) - centroid.row(f)).norm());
  }
  Eigen::MatrixXd midpoint(eb, 3);
  double edge_half = 0;
  for (Eigen::Index e = 0; e < eb; ++e) {
    midpoint.row(e) = (body.V.row(body.E(e, 0)) + body.V.row(body.E(e, 1))) / 2;
    edge_half = std::max(edge_half, (body.V.row(body.E(e, 0)) - midpoint.row(e)).norm());
  }
  body.index = std::make_shared<const SurfaceIndex>(body.V, PointKdTree(centroid), PointKdTree(midpoint), face_reach,
                                                    edge_half);
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
  const PointKdTree& faces = index.faces;
  const double face_reach = index.face_reach;

  // The KD-tree's spheres are loose (every face gets the largest reach): boxes around each
  // primitive's sweep keep only the pairs that can really come within `distance`.
  std::vector<Box> face_box(static_cast<size_t>(mb));
  for (Eigen::Index f = 0; f < mb; ++f)
    for (int k = 0; k < 3; ++k) face_box[size_t(f)].add(body.V, body_motion, body.F(f, k));
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    Box vertex;
    vertex.add(x, dx, int(i));
    for (int f : faces.within_radius_of(x.row(i).transpose(), distance + step(i) + body_step + face_reach))
      if (vertex.near(face_box[size_t(f)], distance)) out.vertex_face.push_back({int(i), f});
  }

  if (eb == 0 || cloth_edges.rows() == 0) return out;
  const double body_half = index.edge_half;
  std::vector<Box> edge_box(static_cast<size_t>(eb));
  for (Eigen::Index e = 0; e < eb; ++e)
    for (int k = 0; k < 2; ++k) edge_box[size_t(e)].add(body.V, body_motion, body.E(e, k));
  const PointKdTree& edges = index.edges;
  for (Eigen::Index e = 0; e < cloth_edges.rows(); ++e) {
    const int a = cloth_edges(e, 0), b = cloth_edges(e, 1);
    const Eigen::Vector3d mid = (x.row(a) + x.row(b)).transpose() / 2;
    const double half = (x.row(a) - x.row(b)).norm() / 2, moved = std::max(step(a), step(b));
    Box cloth_box;
    cloth_box.add(x, dx, a);
    cloth_box.add(x, dx, b);
    for (int be : edges.within_radius_of(mid, distance + moved + body_step + half + body_half))
      if (cloth_box.near(edge_box[size_t(be)], distance)) out.edge_edge.push_back({int(e), be});
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

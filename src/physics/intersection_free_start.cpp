#include "pb4u/physics/intersection_free_start.h"

#include <algorithm>
#include <array>

#include "pb4u/body/project_onto_body.h"
#include "pb4u/physics/barrier_potential.h"
#include "pb4u/physics/pair_distances.h"

namespace pb4u {
namespace {

// Rounds of pushing the ends of edges that cut through the body further out (the offset
// doubles: d_hat x 1, 2, 4, 8, 16).
constexpr int kMaxPushRounds = 5;
// Vertices closer than this fraction of d_hat to the body are pushed out to d_hat; pairs
// closer than kTouching x d_hat after the push-out exclude their cloth vertices.
constexpr double kPushBelow = 0.1;
constexpr double kTouching = 1e-2;

}  // namespace

std::vector<char> vertices_not_free_of(const Eigen::MatrixXd& x, const Eigen::MatrixXi& cloth_edges,
                                       const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, double d_hat) {
  const ContactSurface body = make_contact_surface(V, F);
  std::vector<char> out(size_t(x.rows()), 0);
  const Eigen::VectorXd signed_distance = project_onto_body(x, V, F).distance;
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    if (signed_distance(i) < 0) out[size_t(i)] = 1;
  for (int e : cloth_edges_through_body(x, cloth_edges, body)) out[size_t(cloth_edges(e, 0))] = out[size_t(cloth_edges(e, 1))] = 1;
  const double touching = kTouching * d_hat;
  const ContactCandidates near = contact_candidates(x, {}, cloth_edges, body, {}, touching);
  for_each_pair_distance(x, cloth_edges, body, near,
                         [&](const PrimitiveDistance& d, const std::array<int, 4>& points, int cloth_points) {
    if (d.distance < touching)
      for (int i = 0; i < cloth_points; ++i) out[size_t(points[i])] = 1;
  });
  return out;
}

int push_pinned_edges_free_of_body(Eigen::MatrixXd& x, const std::vector<int>& pinned, const Eigen::MatrixXi& edges,
                                   const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, double step, int max_rounds) {
  // The pinned vertices and the edges between two of them, numbered among themselves.
  std::vector<int> local(size_t(x.rows()), -1);
  for (size_t k = 0; k < pinned.size(); ++k) local[size_t(pinned[k])] = int(k);
  std::vector<std::array<int, 2>> kept;
  for (Eigen::Index e = 0; e < edges.rows(); ++e) {
    const int a = local[size_t(edges(e, 0))], b = local[size_t(edges(e, 1))];
    if (a >= 0 && b >= 0) kept.push_back({a, b});
  }
  if (kept.empty()) return 0;
  Eigen::MatrixXi band(Eigen::Index(kept.size()), 2);
  for (size_t e = 0; e < kept.size(); ++e) band.row(Eigen::Index(e)) << kept[e][0], kept[e][1];
  Eigen::MatrixXd p(Eigen::Index(pinned.size()), 3);
  for (size_t k = 0; k < pinned.size(); ++k) p.row(Eigen::Index(k)) = x.row(pinned[k]);
  const ContactSurface body = make_contact_surface(V, F);
  std::vector<int> through = cloth_edges_through_body(p, band, body);
  if (through.empty()) return 0;
  const BodyProjection side(V, F);
  for (int round = 0; round < max_rounds && !through.empty(); ++round) {
    std::vector<char> push(pinned.size(), 0);
    for (int e : through) push[size_t(band(e, 0))] = push[size_t(band(e, 1))] = 1;
    const Eigen::MatrixXd outward = side.project(p).outward;
    for (size_t k = 0; k < pinned.size(); ++k)
      if (push[k]) p.row(Eigen::Index(k)) += step * outward.row(Eigen::Index(k));
    through = cloth_edges_through_body(p, band, body);
  }
  for (size_t k = 0; k < pinned.size(); ++k) x.row(pinned[k]) = p.row(Eigen::Index(k));
  return int(through.size());
}

FeasibleStart intersection_free_start(const Eigen::MatrixXd& x_t, const Eigen::MatrixXd& target,
                                      const Eigen::MatrixXi& cloth_edges, const Eigen::MatrixXd& body_t,
                                      const Eigen::MatrixXi& body_faces, double d_hat) {
  FeasibleStart out;
  out.x = x_t;
  const Eigen::Index n = x_t.rows();
  const ContactSurface body = make_contact_surface(body_t, body_faces);
  std::vector<char> moved(size_t(n), 0), push(size_t(n), 0);
  std::vector<int> through;
  double offset = d_hat;
  const BodyProjection side(body_t, body_faces);
  for (int round = 0; round < kMaxPushRounds; ++round, offset *= 2) {
    const SurfaceProjection p = side.project(out.x);
    bool any = false;
    for (Eigen::Index i = 0; i < n; ++i)
      if (p.distance(i) < kPushBelow * d_hat || push[size_t(i)]) {
        out.x.row(i) = p.closest.row(i) + (std::max(p.distance(i), 0.0) + offset) * p.outward.row(i);
        moved[size_t(i)] = 1;
        any = true;
      }
    std::fill(push.begin(), push.end(), 0);
    through = cloth_edges_through_body(out.x, cloth_edges, body);
    for (int e : through) push[size_t(cloth_edges(e, 0))] = push[size_t(cloth_edges(e, 1))] = 1;
    if (!any && through.empty()) break;
  }
  out.pushed_out = int(std::count(moved.begin(), moved.end(), 1));
  out.pushed = moved;
  // What the rounds left (edges through the body, pairs touching it: a pushed edge can come to
  // rest on a body edge) leaves contact.
  out.excluded = vertices_not_free_of(out.x, cloth_edges, body_t, body_faces, d_hat);
  out.excluded_count = int(std::count(out.excluded.begin(), out.excluded.end(), 1));
  // Towards the target (pins included), as far as CCD allows.
  const Eigen::MatrixXd dx = target - out.x;
  ContactCandidates c = contact_candidates(out.x, dx, cloth_edges, body, {}, 0.0);
  drop_pairs_of(out.excluded, cloth_edges, &c);
  out.target_progress = max_safe_step(out.x, dx, cloth_edges, body, {}, c);
  out.x += out.target_progress * dx;
  return out;
}

}  // namespace pb4u

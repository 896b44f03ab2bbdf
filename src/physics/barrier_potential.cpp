#include "pb4u/physics/barrier_potential.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

#include "pb4u/physics/additive_ccd.h"
#include "pb4u/physics/barrier.h"
#include "pb4u/physics/pair_distances.h"
#include "pb4u/spatial/segments_through_surface.h"

namespace pb4u {
namespace {

// The Hessian's curvature is taken no closer than this fraction of d_hat: b'' grows as
// (d_hat / d)^2, and pairs a few picometres apart (carried along with the body) made it 1e18
// N/m beside 1 N/m of inertia, which the LDLT cannot factorise. It only shapes the step: the
// line search and CCD still keep every pair apart.
constexpr double kHessianDistance = 1e-3;

}  // namespace

BarrierValue barrier_potential(const Eigen::MatrixXd& x, const Eigen::MatrixXi& cloth_edges,
                               const ContactSurface& body, const ContactCandidates& candidates,
                               const BarrierSettings& s, Eigen::MatrixXd* gradient,
                               Eigen::VectorXd* curvature, CoordinateHessian* hessian) {
  BarrierValue out;
  out.min_distance = std::numeric_limits<double>::infinity();
  for_each_pair_distance(x, cloth_edges, body, candidates,
                         [&](const PrimitiveDistance& d, const std::array<int, 4>& points, int cloth_points) {
    out.min_distance = std::min(out.min_distance, d.distance);
    if (d.distance >= s.d_hat) return;
    ++out.active;
    out.energy += s.stiffness * barrier(d.distance, s.d_hat);
    // Only the cloth's points move in the solve: the derivatives of the first one (vertex) or
    // two (edge) of the four points.
    const double k = curvature ? s.stiffness * barrier_second_derivative(d.distance, s.d_hat) : 0;
    if (hessian)  // no closer than kHessianDistance x d_hat, so the matrix stays factorisable
      add_outer_product(points.data(), cloth_points, d.gradient.data(),
                        s.stiffness * barrier_second_derivative(std::max(d.distance, kHessianDistance * s.d_hat), s.d_hat),
                        hessian);
    const double scale = s.stiffness * barrier_derivative(d.distance, s.d_hat);
    for (int i = 0; i < cloth_points; ++i) {
      if (curvature) (*curvature)(points[i]) += k * d.gradient.segment<3>(3 * i).squaredNorm();
      if (gradient) gradient->row(points[i]) += scale * d.gradient.segment<3>(3 * i).transpose();
    }
  });
  if (out.min_distance <= 0) out.energy = std::numeric_limits<double>::infinity();
  return out;
}

namespace {

// Additive CCD of each candidate pair over the step (cloth by dx, body by body_motion, either
// empty: still), up to options.t_max, which `visit` may lower as it goes: visit(t, cloth points,
// how many of them) returns false to stop.
template <typename Visit>
void for_each_pair_impact(const Eigen::MatrixXd& x, const Eigen::MatrixXd& dx, const Eigen::MatrixXi& cloth_edges,
                          const ContactSurface& body, const Eigen::MatrixXd& body_motion,
                          const ContactCandidates& candidates, AdditiveCcdOptions& options, Visit visit) {
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  auto cloth_step = [&](int i) { return dx.rows() ? point_row(dx, i) : zero; };
  auto body_step = [&](int j) { return body_motion.rows() ? point_row(body_motion, j) : zero; };
  for (const auto& [v, f] : candidates.vertex_face) {
    const int a = body.F(f, 0), b = body.F(f, 1), c = body.F(f, 2);
    const int points[2] = {v, v};
    if (!visit(point_triangle_ccd(point_row(x, v), point_row(body.V, a), point_row(body.V, b), point_row(body.V, c),
                                  cloth_step(v), body_step(a), body_step(b), body_step(c), options),
               points, 1))
      return;
  }
  for (const auto& [e, be] : candidates.edge_edge) {
    const int a = cloth_edges(e, 0), b = cloth_edges(e, 1), c = body.E(be, 0), d = body.E(be, 1);
    const int points[2] = {a, b};
    if (!visit(edge_edge_ccd(point_row(x, a), point_row(x, b), point_row(body.V, c), point_row(body.V, d),
                             cloth_step(a), cloth_step(b), body_step(c), body_step(d), options),
               points, 2))
      return;
  }
}

}  // namespace

double max_safe_step(const Eigen::MatrixXd& x, const Eigen::MatrixXd& dx, const Eigen::MatrixXi& cloth_edges,
                     const ContactSurface& body, const Eigen::MatrixXd& body_motion,
                     const ContactCandidates& candidates) {
  AdditiveCcdOptions options;
  for_each_pair_impact(x, dx, cloth_edges, body, body_motion, candidates, options,
                       [&](double t, const int*, int) {
                         options.t_max = std::min(options.t_max, t);
                         return options.t_max > 0;
                       });
  return std::max(options.t_max, 0.0);
}

std::vector<char> vertices_holding_step(const Eigen::MatrixXd& x, const Eigen::MatrixXd& dx,
                                        const Eigen::MatrixXi& cloth_edges, const ContactSurface& body,
                                        const Eigen::MatrixXd& body_motion, const ContactCandidates& candidates,
                                        double below) {
  AdditiveCcdOptions options;
  options.t_max = below;  // a pair is only followed as far as `below`
  std::vector<char> out(size_t(x.rows()), 0);
  for_each_pair_impact(x, dx, cloth_edges, body, body_motion, candidates, options,
                       [&](double t, const int* points, int count) {
                         if (t < below)
                           for (int i = 0; i < count; ++i) out[size_t(points[i])] = 1;
                         return true;
                       });
  return out;
}

std::vector<int> cloth_edges_through_body(const Eigen::MatrixXd& x, const Eigen::MatrixXi& cloth_edges,
                                          const ContactSurface& body) {
  // A crossing point lies within half the edge of one of its ends: the faces near each end,
  // at that radius, hold every face the edge can cross.
  double half = 0;
  for (Eigen::Index e = 0; e < cloth_edges.rows(); ++e)
    half = std::max(half, (x.row(cloth_edges(e, 0)) - x.row(cloth_edges(e, 1))).norm() / 2);
  const ContactCandidates near = contact_candidates(x, {}, Eigen::MatrixXi(), body, {}, half);
  std::vector<std::vector<int>> faces_near(size_t(x.rows()));
  for (const auto& [v, f] : near.vertex_face) faces_near[size_t(v)].push_back(f);
  std::vector<int> through;
  for (Eigen::Index e = 0; e < cloth_edges.rows(); ++e) {
    const int a = cloth_edges(e, 0), b = cloth_edges(e, 1);
    bool hit = false;
    for (int end : {a, b})
      for (int f : faces_near[size_t(end)])
        hit = hit || segment_crosses_triangle(point_row(x, a), point_row(x, b), point_row(body.V, body.F(f, 0)),
                                              point_row(body.V, body.F(f, 1)), point_row(body.V, body.F(f, 2)));
    if (hit) through.push_back(int(e));
  }
  return through;
}

}  // namespace pb4u

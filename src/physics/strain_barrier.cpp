#include "pb4u/physics/strain_barrier.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pb4u {
namespace {

// IPC's barrier and its first two derivatives in g, for 0 < g < g_hat.
double barrier(double g, double g_hat) { return -(g - g_hat) * (g - g_hat) * std::log(g / g_hat); }
double barrier_d1(double g, double g_hat) { return (g_hat - g) * (2 * std::log(g / g_hat) - g_hat / g + 1); }
double barrier_d2(double g, double g_hat) {
  return -2 * std::log(g / g_hat) + (g_hat - g) * (g_hat + 3 * g) / (g * g);
}

}  // namespace

StrainBarrierValue strain_barrier(const Eigen::MatrixXd& x, const Eigen::MatrixXi& edges, const Eigen::VectorXd& rest,
                                  const StrainBarrierSettings& s, const std::vector<char>& excluded,
                                  Eigen::MatrixXd* gradient, Eigen::VectorXd* curvature,
                                  CoordinateHessian* hessian) {
  StrainBarrierValue out;
  for (Eigen::Index e = 0; e < edges.rows(); ++e) {
    if (!excluded.empty() && excluded[size_t(e)]) continue;
    const int i = edges(e, 0), j = edges(e, 1);
    const Eigen::RowVector3d d = x.row(i) - x.row(j);
    const double length = d.norm();
    const double strain = length / rest(e) - 1;
    out.max_strain = std::max(out.max_strain, strain);
    const double g = s.limit - strain;
    if (g >= s.gap) continue;
    if (!(g > 0)) {
      out.energy = std::numeric_limits<double>::infinity();
      continue;
    }
    ++out.active;
    out.energy += s.stiffness * barrier(g, s.gap);
    // dg/dx_i = -d / (|d| L), dg/dx_j = +d / (|d| L).
    const Eigen::RowVector3d dg_dxi = -d / (length * rest(e));
    if (gradient) {
      const double b1 = s.stiffness * barrier_d1(g, s.gap);
      gradient->row(i) += b1 * dg_dxi;
      gradient->row(j) -= b1 * dg_dxi;
    }
    if (curvature) {
      const double c = s.stiffness * barrier_d2(g, s.gap) / (rest(e) * rest(e));
      (*curvature)(i) += c;
      (*curvature)(j) += c;
    }
    if (hessian) {
      const Eigen::Vector3d u = d.transpose() / length;
      const Eigen::Matrix3d along = u * u.transpose();
      // Its curvature taken no nearer the limit than a thousandth of the band, as the contact
      // barrier's (barrier_potential.cpp): it only shapes the step, the step filter keeps the limit.
      const double gh = std::max(g, 1e-3 * s.gap);
      const Eigen::Matrix3d A =
          s.stiffness * (barrier_d2(gh, s.gap) / (rest(e) * rest(e)) * along -
                         barrier_d1(gh, s.gap) / (rest(e) * length) * (Eigen::Matrix3d::Identity() - along));
      hessian->add(i, i, A);
      hessian->add(j, j, A);
      hessian->add(i, j, -A);
      hessian->add(j, i, -A);
    }
  }
  return out;
}

double max_strain_step(const Eigen::MatrixXd& x, const Eigen::MatrixXd& dx, const Eigen::MatrixXi& edges,
                       const Eigen::VectorXd& rest, double limit, const std::vector<char>& excluded) {
  double t = 1.0;
  for (Eigen::Index e = 0; e < edges.rows(); ++e) {
    if (!excluded.empty() && excluded[size_t(e)]) continue;
    const int i = edges(e, 0), j = edges(e, 1);
    const Eigen::RowVector3d d = x.row(i) - x.row(j), dd = dx.row(i) - dx.row(j);
    // |d + a dd|^2 = R^2: a^2 |dd|^2 + 2 a d.dd + |d|^2 - R^2 = 0, with |d| < R at a = 0.
    const double R = (1 + limit) * rest(e);
    const double qa = dd.squaredNorm(), qb = 2 * d.dot(dd), qc = d.squaredNorm() - R * R;
    if (qa <= 0 || qc >= 0) continue;  // no motion, or already excluded-worthy (caller's business)
    const double root = (-qb + std::sqrt(qb * qb - 4 * qa * qc)) / (2 * qa);  // the positive root
    t = std::min(t, 0.8 * root);
  }
  return t;
}

std::vector<char> edges_over_strain(const Eigen::MatrixXd& x, const Eigen::MatrixXi& edges, const Eigen::VectorXd& rest,
                                    double limit) {
  std::vector<char> over(size_t(edges.rows()), 0);
  for (Eigen::Index e = 0; e < edges.rows(); ++e)
    over[size_t(e)] = (x.row(edges(e, 0)) - x.row(edges(e, 1))).norm() >= (1 + limit) * rest(e);
  return over;
}

Eigen::MatrixXd shorten_overstretched_edges(const Eigen::MatrixXd& x, const Eigen::MatrixXi& edges,
                                            const Eigen::VectorXd& rest, double limit, const std::vector<char>& fixed,
                                            int sweeps) {
  Eigen::MatrixXd y = x;
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    bool changed = false;
    for (Eigen::Index k = 0; k < edges.rows(); ++k) {
      const Eigen::Index e = sweep % 2 ? edges.rows() - 1 - k : k;
      const int i = edges(e, 0), j = edges(e, 1);
      const bool fi = !fixed.empty() && fixed[size_t(i)], fj = !fixed.empty() && fixed[size_t(j)];
      if (fi && fj) continue;
      const Eigen::RowVector3d d = y.row(i) - y.row(j);
      const double length = d.norm(), target = (1 + limit) * rest(e);
      if (length <= target) continue;
      const Eigen::RowVector3d cut = (length - target) / length * d;  // to remove from i - j
      if (fi) y.row(j) += cut;
      else if (fj) y.row(i) -= cut;
      else {
        y.row(i) -= 0.5 * cut;
        y.row(j) += 0.5 * cut;
      }
      changed = true;
    }
    if (!changed) break;
  }
  return y;
}

}  // namespace pb4u

#include "pb4u/physics/area_barrier.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

#include "pb4u/mesh/geometry.h"
#include "pb4u/physics/barrier.h"

namespace pb4u {
namespace {

// [a]x: the matrix of a x .
Eigen::Matrix3d cross_matrix(const Eigen::Vector3d& a) {
  Eigen::Matrix3d m;
  m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return m;
}

Eigen::Vector3d vertex(const Eigen::MatrixXd& x, int i) { return x.row(i).transpose(); }

// The smallest t > 0 with a t^2 + b t + c = 0 (c > 0), or +infinity.
double first_positive_root(double a, double b, double c) {
  double t = std::numeric_limits<double>::infinity();
  if (std::abs(a) <= 1e-14 * (std::abs(b) + c)) {
    if (b < 0) t = -c / b;
    return t;
  }
  const double disc = b * b - 4 * a * c;
  if (disc < 0) return t;
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  for (double root : {q / a, q != 0 ? c / q : std::numeric_limits<double>::infinity()})
    if (root > 0) t = std::min(t, root);
  return t;
}

}  // namespace

double triangle_area(const Eigen::Vector3d& x0, const Eigen::Vector3d& x1, const Eigen::Vector3d& x2,
                     Eigen::Matrix<double, 9, 1>* gradient, Eigen::Matrix<double, 9, 9>* hessian) {
  const Eigen::Vector3d u = x1 - x0, v = x2 - x0, c = u.cross(v);
  const double norm = c.norm();
  if (gradient) gradient->setZero();
  if (hessian) hessian->setZero();
  if (!(norm > 0)) return 0;
  const Eigen::Vector3d n = c / norm;
  // c = u x v: dc/dx1 = -[v]x, dc/dx2 = [u]x, dc/dx0 = [v]x - [u]x; dA = n . dc / 2.
  Eigen::Matrix<double, 3, 9> J;
  J << cross_matrix(v) - cross_matrix(u), -cross_matrix(v), cross_matrix(u);
  if (gradient) *gradient = 0.5 * J.transpose() * n;
  if (hessian) {
    // d2A = (J^T (I - n n^T) J / |c| + d2(n . c) with n held) / 2; n . c = u^T M v, M = -[n]x,
    // and u = x1 - x0, v = x2 - x0 map (u, v) to the vertices with coefficients tu, tv.
    *hessian = J.transpose() * (Eigen::Matrix3d::Identity() - n * n.transpose()) * J / norm;
    const Eigen::Matrix3d M = -cross_matrix(n);
    const double tu[3] = {-1, 1, 0}, tv[3] = {-1, 0, 1};
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        hessian->block<3, 3>(3 * a, 3 * b) += tu[a] * tv[b] * M + tv[a] * tu[b] * M.transpose();
    *hessian *= 0.5;
  }
  return 0.5 * norm;
}

AreaBarrierValue area_barrier(const Eigen::MatrixXd& x, const Eigen::MatrixXi& faces, const Eigen::VectorXd& rest_area,
                              const AreaBarrierSettings& s, const std::vector<char>& excluded,
                              Eigen::MatrixXd* gradient, Eigen::VectorXd* curvature, CoordinateHessian* hessian) {
  AreaBarrierValue out;
  Eigen::Matrix<double, 9, 1> dA;
  Eigen::Matrix<double, 9, 9> d2A;
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    if (!excluded.empty() && excluded[size_t(f)]) continue;
    const double A0 = rest_area(f);
    if (!(A0 > 0)) continue;
    const int v[3] = {faces(f, 0), faces(f, 1), faces(f, 2)};
    // The area alone first: most faces are far from the band.
    const double A = triangle_area(vertex(x, v[0]), vertex(x, v[1]), vertex(x, v[2]));
    const double r = A / A0;
    out.min_ratio = std::min(out.min_ratio, r);
    if (r >= s.gap) continue;
    if (!(r > 0)) {
      out.energy = std::numeric_limits<double>::infinity();
      continue;
    }
    ++out.active;
    out.energy += s.stiffness * A0 * barrier(r, s.gap);
    const bool second = curvature || hessian;
    triangle_area(vertex(x, v[0]), vertex(x, v[1]), vertex(x, v[2]), &dA, hessian ? &d2A : nullptr);
    // dE/dx = kappa b'(r) dA/dx (A0 cancels).
    if (gradient) {
      const double b1 = s.stiffness * barrier_derivative(r, s.gap);
      for (int a = 0; a < 3; ++a) gradient->row(v[a]) += b1 * dA.segment<3>(3 * a).transpose();
    }
    if (!second) continue;
    // Its curvature taken no nearer the pole than a thousandth of the band, as the other
    // barriers': it only shapes the step, the step filter keeps the face from collapsing.
    const double rh = std::max(r, 1e-3 * s.gap);
    const double b2 = s.stiffness * barrier_second_derivative(rh, s.gap) / A0;
    if (curvature)
      for (int a = 0; a < 3; ++a) (*curvature)(v[a]) += b2 * dA.segment<3>(3 * a).squaredNorm();
    if (hessian) {
      // kappa (b''(r) / A0 dA dA^T + b'(r) d2A), projected per face.
      const Eigen::Matrix<double, 9, 9> H =
          b2 * dA * dA.transpose() + s.stiffness * barrier_derivative(rh, s.gap) * d2A;
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> eigen(0.5 * (H + H.transpose()));
      const Eigen::Matrix<double, 9, 9> P =
          eigen.eigenvectors() * eigen.eigenvalues().cwiseMax(0.0).asDiagonal() * eigen.eigenvectors().transpose();
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) hessian->add(v[a], v[b], P.block<3, 3>(3 * a, 3 * b));
    }
  }
  return out;
}

double max_area_step(const Eigen::MatrixXd& x, const Eigen::MatrixXd& dx, const Eigen::MatrixXi& faces,
                     const std::vector<char>& excluded) {
  double t = 1.0;
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    if (!excluded.empty() && excluded[size_t(f)]) continue;
    const int i = faces(f, 0), j = faces(f, 1), k = faces(f, 2);
    const Eigen::Vector3d u = vertex(x, j) - vertex(x, i), v = vertex(x, k) - vertex(x, i);
    const Eigen::Vector3d du = vertex(dx, j) - vertex(dx, i), dv = vertex(dx, k) - vertex(dx, i);
    const Eigen::Vector3d c = u.cross(v);
    const double norm = c.norm();
    if (!(norm > 0)) continue;  // degenerate already: the caller leaves it out
    const Eigen::Vector3d n = c / norm;
    // n . ((u + t du) x (v + t dv)) = norm + t n.(u x dv + du x v) + t^2 n.(du x dv)
    const double root = first_positive_root(n.dot(du.cross(dv)), n.dot(u.cross(dv) + du.cross(v)), norm);
    t = std::min(t, 0.8 * root);
  }
  return t;
}

std::vector<char> faces_below_area(const Eigen::MatrixXd& x, const Eigen::MatrixXi& faces,
                                   const Eigen::VectorXd& rest_area, double ratio) {
  const Eigen::VectorXd A = face_areas(x, faces);
  std::vector<char> below(size_t(faces.rows()), 0);
  for (Eigen::Index f = 0; f < faces.rows(); ++f) below[size_t(f)] = !(rest_area(f) > 0) || A(f) <= ratio * rest_area(f);
  return below;
}

}  // namespace pb4u

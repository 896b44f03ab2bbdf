#include "pb4u/mesh/geometry.h"

#include <Eigen/Geometry>

#include "pb4u/mesh/edges.h"

namespace pb4u {
namespace {
Eigen::Vector3d face_cross(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int f) {
  Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
  return (b - a).cross(c - a);
}
}  // namespace

Eigen::VectorXd face_areas(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Eigen::VectorXd A(F.rows());
  for (int f = 0; f < F.rows(); ++f) A(f) = 0.5 * face_cross(V, F, f).norm();
  return A;
}

Eigen::MatrixXd face_normals(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Eigen::MatrixXd N(F.rows(), 3);
  for (int f = 0; f < F.rows(); ++f) {
    Eigen::Vector3d c = face_cross(V, F, f);
    double n = c.norm();
    N.row(f) = n > 0 ? Eigen::Vector3d(c / n) : Eigen::Vector3d::Zero();
  }
  return N;
}

Eigen::MatrixXd vertex_normals(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(V.rows(), 3);
  for (int f = 0; f < F.rows(); ++f) {
    Eigen::RowVector3d c = face_cross(V, F, f).transpose();  // |c| = 2 * area: area weighting
    for (int k = 0; k < 3; ++k) N.row(F(f, k)) += c;
  }
  for (int v = 0; v < N.rows(); ++v) {
    double n = N.row(v).norm();
    if (n > 0) N.row(v) /= n;
  }
  return N;
}

Eigen::VectorXd vertex_masses(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, double density) {
  Eigen::VectorXd m = Eigen::VectorXd::Zero(V.rows());
  Eigen::VectorXd A = face_areas(V, F);
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) m(F(f, k)) += density * A(f) / 3.0;
  return m;
}

Eigen::VectorXd edge_lengths(const Eigen::MatrixXd& V, const Eigen::MatrixXi& E) {
  Eigen::VectorXd L(E.rows());
  for (int e = 0; e < E.rows(); ++e) L(e) = (V.row(E(e, 0)) - V.row(E(e, 1))).norm();
  return L;
}

double mean_edge_length(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Eigen::VectorXd L = edge_lengths(V, unique_edges(F));
  return L.size() ? L.mean() : 0.0;
}

Eigen::VectorXd vertex_mean_edge_length(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Eigen::MatrixXi E = unique_edges(F);
  Eigen::VectorXd L = edge_lengths(V, E);
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(V.rows()), count = Eigen::VectorXd::Zero(V.rows());
  for (int e = 0; e < E.rows(); ++e)
    for (int k = 0; k < 2; ++k) {
      sum(E(e, k)) += L(e);
      count(E(e, k)) += 1;
    }
  return (count.array() > 0).select(sum.array() / count.array().max(1.0), 0.0);
}

Eigen::Matrix<double, 2, 3> bounding_box(const Eigen::MatrixXd& V) {
  Eigen::Matrix<double, 2, 3> box = Eigen::Matrix<double, 2, 3>::Zero();
  if (V.rows() == 0) return box;
  box.row(0) = V.colwise().minCoeff();
  box.row(1) = V.colwise().maxCoeff();
  return box;
}

int count_degenerate_faces(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, double min_area) {
  int count = 0;
  Eigen::VectorXd A = face_areas(V, F);
  for (int f = 0; f < F.rows(); ++f) {
    bool repeated = F(f, 0) == F(f, 1) || F(f, 1) == F(f, 2) || F(f, 0) == F(f, 2);
    count += repeated || A(f) < min_area;
  }
  return count;
}

}  // namespace pb4u

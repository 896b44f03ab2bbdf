#pragma once
// A body as an implicit surface: a smooth union of tapered capsules along the bones.
// The field is 1-Lipschitz (each capsule distance is, and the polynomial smooth minimum
// blends gradients convexly), so a point where it equals g lies at least g from the body:
// garments polygonised at level g never penetrate it.
#include <Eigen/Core>
#include <vector>

namespace pb4u {

// Segment a-b (m) with radius ra at a and rb at b, moved by skeleton joint `joint`.
struct Capsule {
  Eigen::Vector3d a, b;
  double ra = 0, rb = 0;
  int joint = 0;
  // Approximate signed distance (m): distance to the axis minus the interpolated radius.
  double distance(const Eigen::Vector3d& p) const;
};

struct ImplicitBody {
  std::vector<Capsule> capsules;
  double blend = 0.0;  // m, width of the smooth union between capsules

  // Field value (m): negative inside, positive outside.
  double value(const Eigen::Vector3d& p) const;
  // Axis-aligned bounds of the solid, row 0 min, row 1 max.
  Eigen::Matrix<double, 2, 3> bounds() const;
};

// Polynomial smooth minimum of a and b over width k (m); min(a, b) when k = 0.
double smooth_min(double a, double b, double k);

// A regular grid of nodes origin + (i, j, k) * cell, i < nx, j < ny, k < nz; node values
// are stored at index (i * ny + j) * nz + k.
struct Grid {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double cell = 0.01;  // m
  int nx = 0, ny = 0, nz = 0;
  Eigen::Index size() const { return Eigen::Index(nx) * ny * nz; }
  Eigen::Vector3d node(int i, int j, int k) const {
    return origin + cell * Eigen::Vector3d(i, j, k);
  }
};

// A grid with spacing `cell` (m) covering `bounds` grown by `margin` (m).
Grid grid_around(const Eigen::Matrix<double, 2, 3>& bounds, double cell, double margin);

// The body's field at every grid node. Values up to `exact_up_to` (m) are exact; nodes far
// from every capsule hold some larger positive value, which is all polygonisation of a
// level set at or below `exact_up_to` needs.
Eigen::VectorXd sample_implicit(const ImplicitBody& body, const Grid& grid, double exact_up_to = 0.0);

}  // namespace pb4u

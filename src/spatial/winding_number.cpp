#include "pb4u/spatial/winding_number.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "pb4u/util/error.h"

namespace pb4u {

struct WindingNumbers::Impl {
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  double y0 = 0, z0 = 0, cell = 1;
  int ny = 1, nz = 1;
  std::vector<std::vector<int>> cells;  // faces whose (y, z) box overlaps each cell, row-major in y

  int cell_y(double y) const { return std::clamp(int(std::floor((y - y0) / cell)), 0, ny - 1); }
  int cell_z(double z) const { return std::clamp(int(std::floor((z - z0) / cell)), 0, nz - 1); }
};

WindingNumbers::WindingNumbers(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) : impl_(std::make_unique<Impl>()) {
  if (V.rows() == 0 || F.rows() == 0) throw Error("winding numbers: empty surface");
  if (!V.allFinite()) throw Error("winding numbers: a surface vertex is not finite");
  if (F.minCoeff() < 0 || F.maxCoeff() >= V.rows())
    throw Error("winding numbers: a face index is outside 0.." + std::to_string(V.rows() - 1));
  Impl& s = *impl_;
  s.V = V;
  s.F = F;
  const double y1 = V.col(1).maxCoeff(), z1 = V.col(2).maxCoeff();
  s.y0 = V.col(1).minCoeff();
  s.z0 = V.col(2).minCoeff();
  // About two faces' width per cell: sqrt(faces) cells along the longer side.
  const double extent = std::max({y1 - s.y0, z1 - s.z0, 1e-9});
  const int along = std::clamp(int(std::sqrt(double(F.rows()))), 1, 512);
  s.cell = extent / along;
  s.ny = std::max(1, int(std::ceil((y1 - s.y0) / s.cell)));
  s.nz = std::max(1, int(std::ceil((z1 - s.z0) / s.cell)));
  s.cells.assign(size_t(s.ny) * s.nz, {});
  for (int f = 0; f < F.rows(); ++f) {
    double ylo = V(F(f, 0), 1), yhi = ylo, zlo = V(F(f, 0), 2), zhi = zlo;
    for (int c = 1; c < 3; ++c) {
      ylo = std::min(ylo, V(F(f, c), 1));
      yhi = std::max(yhi, V(F(f, c), 1));
      zlo = std::min(zlo, V(F(f, c), 2));
      zhi = std::max(zhi, V(F(f, c), 2));
    }
    for (int iy = s.cell_y(ylo); iy <= s.cell_y(yhi); ++iy)
      for (int iz = s.cell_z(zlo); iz <= s.cell_z(zhi); ++iz) s.cells[size_t(iy) * s.nz + iz].push_back(f);
  }
}

WindingNumbers::~WindingNumbers() = default;
WindingNumbers::WindingNumbers(WindingNumbers&&) noexcept = default;
WindingNumbers& WindingNumbers::operator=(WindingNumbers&&) noexcept = default;

Eigen::VectorXi WindingNumbers::at(const Eigen::MatrixXd& points) const {
  const Impl& s = *impl_;
  Eigen::VectorXi w = Eigen::VectorXi::Zero(points.rows());
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    const double px = points(i, 0), py = points(i, 1) + 1e-9 * M_SQRT1_2,
                 pz = points(i, 2) + 1e-9 * 0.5773502691896258;
    if (py < s.y0 || pz < s.z0 || py > s.y0 + s.ny * s.cell || pz > s.z0 + s.nz * s.cell) continue;
    int count = 0;
    for (int f : s.cells[size_t(s.cell_y(py)) * s.nz + s.cell_z(pz)]) {
      const Eigen::RowVector3d a = s.V.row(s.F(f, 0)), b = s.V.row(s.F(f, 1)), c = s.V.row(s.F(f, 2));
      // Signed areas of the (y, z) projection: the point is in the projected triangle when all
      // three have the sign of the whole (which is the sign of the normal's x).
      auto orient = [&](const Eigen::RowVector3d& p, const Eigen::RowVector3d& q) {
        return (q(1) - p(1)) * (pz - p(2)) - (q(2) - p(2)) * (py - p(1));
      };
      const double e0 = orient(a, b), e1 = orient(b, c), e2 = orient(c, a);
      const bool positive = e0 > 0 && e1 > 0 && e2 > 0, negative = e0 < 0 && e1 < 0 && e2 < 0;
      if (!positive && !negative) continue;
      // Where the ray meets the face's plane: x with barycentric weights e1, e2, e0 (for a, b, c).
      const double x = (e1 * a(0) + e2 * b(0) + e0 * c(0)) / (e0 + e1 + e2);
      if (x <= px) continue;
      count += positive ? 1 : -1;
    }
    w(i) = count;
  }
  return w;
}

}  // namespace pb4u

#include "pb4u/physics/elastic_solve.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "pb4u/physics/quasi_newton_hessian.h"
#include "pb4u/util/error.h"

namespace pb4u {

void ElasticSolve::factorize(const torch::Tensor& contact_diagonal) {
  Eigen::VectorXd diagonal;
  if (contact_diagonal.defined()) {
    torch::Tensor c = contact_diagonal.detach().to(torch::kCPU, torch::kFloat64).contiguous();
    diagonal = Eigen::Map<const Eigen::VectorXd>(c.data_ptr<double>(), c.numel());
  }
  if (coordinates) {
    add_shared(base, diagonal, row_of_vertex, &hessian);
    const Eigen::SparseMatrix<double> H = hessian.matrix(row_of_vertex);
    // The ordering is redone only when the pattern changed (a Newton step's elastic pattern
    // stays; contact pairs only add blocks where cloth vertices already share a face).
    const bool same = pattern_outer.size() == size_t(H.outerSize() + 1) &&
                      std::equal(pattern_outer.begin(), pattern_outer.end(), H.outerIndexPtr()) &&
                      pattern_inner.size() == size_t(H.nonZeros()) &&
                      std::equal(pattern_inner.begin(), pattern_inner.end(), H.innerIndexPtr());
    if (!same) {
      ldlt.analyzePattern(H);
      pattern_outer.assign(H.outerIndexPtr(), H.outerIndexPtr() + H.outerSize() + 1);
      pattern_inner.assign(H.innerIndexPtr(), H.innerIndexPtr() + H.nonZeros());
    }
    factorize_shifted(H);
  } else {
    Eigen::SparseMatrix<double> H = base;
    if (diagonal.size()) H.diagonal() += diagonal;
    factorize_shifted(H);
  }
}

// A pivot lost to rounding (entries ~1e19 beside ~1e2, from the Newton Hessian of a sliver
// triangle or a barrier pair all but touching) fails the LDLT although the matrix is positive
// semi-definite plus inertia: the factorisation is tried again with the diagonal shifted by
// a growing fraction of its largest entry (Levenberg-Marquardt). The shift only shapes the
// step's direction; the line search and CCD decide how far it goes.
void ElasticSolve::factorize_shifted(const Eigen::SparseMatrix<double>& H) {
  ldlt.factorize(H);
  if (ldlt.info() == Eigen::Success) return;
  const double largest = H.diagonal().cwiseAbs().maxCoeff();
  for (double share = 1e-12; share <= 1e-3 && std::isfinite(largest); share *= 1e3) {
    Eigen::SparseMatrix<double> shifted = H;
    shifted.diagonal().array() += share * largest;
    ldlt.factorize(shifted);
    if (ldlt.info() == Eigen::Success) {
      spdlog::debug("reference solver: the Hessian factorised with its diagonal shifted by {:.3g} "
                    "({:.0e} of its largest entry)",
                    share * largest, share);
      return;
    }
  }
  throw Error("reference solver: the elastic initial Hessian is not positive definite");
}

torch::Tensor ElasticSolve::operator()(const torch::Tensor& r) const {
  torch::Tensor c = r.detach().to(torch::kCPU, torch::kFloat64).contiguous();
  const Eigen::Index k = c.numel() / 3;
  if (coordinates) {
    Eigen::VectorXd X = ldlt.solve(Eigen::Map<const Eigen::VectorXd>(c.data_ptr<double>(), 3 * k));
    return torch::from_blob(X.data(), {k * 3}, torch::kFloat64).to(r.options()).clone();
  }
  Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>> R(c.data_ptr<double>(), k, 3);
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> X = ldlt.solve(R);
  return torch::from_blob(X.data(), {k * 3}, torch::kFloat64).to(r.options()).clone();
}

std::shared_ptr<ElasticSolve> newton_elastic_solve(const torch::Tensor& masses, double dt,
                                                   const std::vector<int>& row_of_vertex, int64_t k) {
  const torch::Tensor mass = masses.to(torch::kCPU, torch::kFloat64).contiguous();
  std::vector<Eigen::Triplet<double>> inertia;
  for (size_t v = 0; v < row_of_vertex.size(); ++v)
    if (row_of_vertex[v] >= 0) {
      const double mv = mass.data_ptr<double>()[v];
      inertia.emplace_back(row_of_vertex[v], row_of_vertex[v], mv > 0 ? mv / (dt * dt) : 1.0);
    }
  auto solve = std::make_shared<ElasticSolve>();
  solve->base.resize(k, k);
  solve->base.setFromTriplets(inertia.begin(), inertia.end());
  solve->row_of_vertex = row_of_vertex;
  solve->coordinates = true;
  solve->hessian = CoordinateHessian(int(row_of_vertex.size()));
  return solve;
}

std::shared_ptr<ElasticSolve> quasi_newton_elastic_solve(const ClothGeometry& cloth, const Material& material,
                                                         double dt, const std::vector<int>& row_of_vertex,
                                                         bool coordinates) {
  auto solve = std::make_shared<ElasticSolve>();
  solve->base = quasi_newton_hessian(cloth, material, dt, row_of_vertex);
  solve->row_of_vertex = row_of_vertex;
  solve->coordinates = coordinates;
  solve->hessian = CoordinateHessian(int(row_of_vertex.size()));
  if (!coordinates) solve->ldlt.analyzePattern(solve->base);
  return solve;
}

}  // namespace pb4u

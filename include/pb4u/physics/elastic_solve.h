#pragma once
// The reference solver's linear solve (reference_solver.h): r -> H^-1 r, with H the elastic
// Hessian factorised by sparse LDL^T.
//   - Quasi-Newton (L-BFGS's initial Hessian): the per-frame part, inertia + rest membrane
//     (quasi_newton_hessian.h), shared by x, y and z (k x k), plus the contacts' current
//     curvature; refactorised only when the contacts change it.
//   - On the coordinates (3k x 3k, coordinate_hessian.h): the same with the barriers' Hessian
//     blocks, and for a Newton step the inertia M / dt^2 with every elastic term's Hessian at the
//     current state added each iteration (`hessian`).
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <torch/torch.h>

#include <memory>
#include <vector>

#include "pb4u/physics/cloth_geometry.h"
#include "pb4u/physics/coordinate_hessian.h"
#include "pb4u/scene/material.h"

namespace pb4u {

struct ElasticSolve {  // not copyable (the factorisation): held by shared_ptr
  Eigen::SparseMatrix<double> base;  // k x k: the part shared by x, y and z
  std::vector<int> row_of_vertex;    // per cloth vertex: its row, -1 for a pin
  bool coordinates = false;
  CoordinateHessian hessian;  // coordinates only: what the contacts (and a Newton step) add to base
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
  std::vector<int> pattern_outer, pattern_inner;  // of the last analysed coordinate Hessian

  // base + `hessian` (coordinates) + contact_diagonal (per free vertex, undefined: none),
  // factorised; throws where even a shifted diagonal cannot be factorised.
  void factorize(const torch::Tensor& contact_diagonal);
  // ldlt of H, with the diagonal shifted where rounding loses a pivot; throws when none works.
  void factorize_shifted(const Eigen::SparseMatrix<double>& H);
  // r (3k, xyz per vertex) -> H^-1 r, in r's options.
  torch::Tensor operator()(const torch::Tensor& r) const;
};

// For Newton steps: base = M / dt^2 on the free vertices (a massless vertex 1 N/m), on the
// coordinates. masses: per cloth vertex (kg); k: the number of free vertices.
std::shared_ptr<ElasticSolve> newton_elastic_solve(const torch::Tensor& masses, double dt,
                                                   const std::vector<int>& row_of_vertex, int64_t k);

// For L-BFGS: base = quasi_newton_hessian(); on the coordinates when the barriers' Hessian blocks
// are kept, else shared by x, y and z (its pattern analysed once).
std::shared_ptr<ElasticSolve> quasi_newton_elastic_solve(const ClothGeometry& cloth, const Material& material,
                                                         double dt, const std::vector<int>& row_of_vertex,
                                                         bool coordinates);

}  // namespace pb4u

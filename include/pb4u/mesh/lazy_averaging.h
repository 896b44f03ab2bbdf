#pragma once
// Lazy neighbour averaging on a mesh's edge graph, f_i <- (f_i + mean of the neighbours' f) / 2,
// as a sparse matrix P (f <- P f). n rounds spread a field over ~0.7 sqrt(n) edge lengths (rms).
// Used to smooth skin weights over the garment and the model's predicted acceleration (detail
// update scaling).
#include <Eigen/Core>
#include <Eigen/Sparse>

#include <cstdint>
#include <vector>

namespace pb4u {

// P for n vertices from directed edges sender -> receiver (each undirected edge listed both
// ways). A vertex without neighbours keeps its value.
template <class Scalar>
Eigen::SparseMatrix<Scalar, Eigen::RowMajor> lazy_averaging_matrix(Eigen::Index n, const int64_t* senders,
                                                                   const int64_t* receivers, Eigen::Index edges) {
  std::vector<int> degree(n, 0);
  for (Eigen::Index k = 0; k < edges; ++k) ++degree[receivers[k]];
  std::vector<Eigen::Triplet<Scalar>> entries;
  entries.reserve(edges + n);
  for (Eigen::Index i = 0; i < n; ++i) entries.emplace_back(int(i), int(i), Scalar(degree[i] > 0 ? 0.5 : 1.0));
  for (Eigen::Index k = 0; k < edges; ++k)
    entries.emplace_back(int(receivers[k]), int(senders[k]), Scalar(0.5) / Scalar(degree[receivers[k]]));
  Eigen::SparseMatrix<Scalar, Eigen::RowMajor> P(n, n);
  P.setFromTriplets(entries.begin(), entries.end());
  return P;
}

// The same from undirected edges (E x 2, each edge once, e.g. unique_edges(F)).
template <class Scalar>
Eigen::SparseMatrix<Scalar, Eigen::RowMajor> lazy_averaging_matrix(Eigen::Index n, const Eigen::MatrixXi& edges) {
  std::vector<int64_t> senders, receivers;
  senders.reserve(2 * edges.rows());
  receivers.reserve(2 * edges.rows());
  for (Eigen::Index e = 0; e < edges.rows(); ++e) {
    senders.push_back(edges(e, 0)), receivers.push_back(edges(e, 1));
    senders.push_back(edges(e, 1)), receivers.push_back(edges(e, 0));
  }
  return lazy_averaging_matrix<Scalar>(n, senders.data(), receivers.data(), Eigen::Index(senders.size()));
}

}  // namespace pb4u

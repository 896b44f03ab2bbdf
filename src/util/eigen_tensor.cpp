#include "pb4u/util/eigen_tensor.h"

namespace pb4u {

torch::Tensor matrix_to_tensor(const Eigen::MatrixXd& m, torch::Dtype dtype, torch::Device device) {
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> r = m;
  return torch::from_blob(r.data(), {r.rows(), r.cols()}, torch::kFloat64).to(device, dtype).clone();
}

torch::Tensor index_matrix_to_tensor(const Eigen::MatrixXi& m, torch::Device device) {
  Eigen::Matrix<int64_t, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> r = m.cast<int64_t>();
  return torch::from_blob(r.data(), {r.rows(), r.cols()}, torch::kInt64).to(device).clone();
}

torch::Tensor index_vector_to_tensor(const Eigen::VectorXi& v, torch::Device device) {
  Eigen::Matrix<int64_t, Eigen::Dynamic, 1> r = v.cast<int64_t>();
  return torch::from_blob(r.data(), {r.size()}, torch::kInt64).to(device).clone();
}

Eigen::MatrixXi index_tensor_to_matrix(const torch::Tensor& t) {
  auto c = t.detach().to(torch::kCPU, torch::kInt32).contiguous();
  Eigen::Map<const Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> m(c.data_ptr<int>(), c.size(0),
                                                                                        c.size(1));
  return m;
}

Eigen::MatrixXd tensor_to_matrix(const torch::Tensor& t) {
  auto c = t.detach().to(torch::kCPU, torch::kFloat64).contiguous();
  Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> m(
      c.data_ptr<double>(), c.size(0), c.size(1));
  return m;
}

}  // namespace pb4u

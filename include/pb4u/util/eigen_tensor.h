#pragma once
// Eigen <-> torch conversions at the stage boundaries (mesh/data are Eigen, graph/physics/model
// are tensors). All copy; none aliases the source.
#include <torch/torch.h>

#include <Eigen/Core>

namespace pb4u {

// (rows, cols) tensor of `m`, row-major, in `dtype` on `device`.
torch::Tensor matrix_to_tensor(const Eigen::MatrixXd& m, torch::Dtype dtype = torch::kFloat64,
                               torch::Device device = torch::kCPU);

// (rows, cols) int64 tensor of an index matrix (faces, hinges, pairs), on `device`.
torch::Tensor index_matrix_to_tensor(const Eigen::MatrixXi& m, torch::Device device = torch::kCPU);

// (n) int64 tensor of an index vector, on `device`.
torch::Tensor index_vector_to_tensor(const Eigen::VectorXi& v, torch::Device device = torch::kCPU);

// A 2-D integer tensor (faces, edges) of any device as an int Eigen matrix.
Eigen::MatrixXi index_tensor_to_matrix(const torch::Tensor& t);

// A 2-D tensor of any float dtype / device as a float64 Eigen matrix.
Eigen::MatrixXd tensor_to_matrix(const torch::Tensor& t);

}  // namespace pb4u

#include "pb4u/graph/garment_topology.h"

#include "pb4u/graph/features.h"
#include "pb4u/mesh/edges.h"
#include "pb4u/mesh/geometry.h"
#include "pb4u/util/error.h"

namespace pb4u {

namespace {
torch::Tensor to_float_tensor(const Eigen::VectorXd& v) {
  return torch::from_blob(const_cast<double*>(v.data()), {v.size()}, torch::kFloat64)
      .to(torch::kFloat32);
}
}  // namespace

GarmentTopology build_garment_topology(const TriMesh& rest, const std::string& where) {
  const int n = rest.num_vertices();
  if (rest.num_faces() == 0) fail_file(where, "garment mesh has no faces");
  if (rest.F.minCoeff() < 0 || rest.F.maxCoeff() >= n)
    fail_file(where, "face index out of range (mesh has " + std::to_string(n) + " vertices)");
  if (!rest.V.allFinite()) fail_file(where, "rest positions are not finite");

  Eigen::MatrixXi E = unique_edges(rest.F);
  Eigen::VectorXd L = edge_lengths(rest.V, E);
  if (L.minCoeff() <= 0) fail_file(where, "zero-length rest edge (weld or clean the mesh first)");

  const int64_t ne = E.rows();
  GarmentTopology topo;
  topo.num_vertices = n;
  topo.mean_edge_length = L.mean();
  auto faces = torch::empty({rest.num_faces(), 3}, torch::kInt64);
  auto fa = faces.accessor<int64_t, 2>();
  for (int f = 0; f < rest.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) fa[f][k] = rest.F(f, k);
  topo.faces = faces;

  topo.senders = torch::empty({2 * ne}, torch::kInt64);
  topo.receivers = torch::empty({2 * ne}, torch::kInt64);
  topo.rest_direction = torch::empty({2 * ne, 3}, torch::kFloat32);
  topo.rest_length = torch::empty({2 * ne}, torch::kFloat32);
  auto s = topo.senders.accessor<int64_t, 1>(), r = topo.receivers.accessor<int64_t, 1>();
  auto dir = topo.rest_direction.accessor<float, 2>();
  auto len = topo.rest_length.accessor<float, 1>();
  for (int64_t e = 0; e < ne; ++e) {
    for (int64_t k = 0; k < 2; ++k) {
      const int64_t d = e + k * ne;
      s[d] = E(e, k);
      r[d] = E(e, 1 - k);
      Eigen::RowVector3d u = (rest.V.row(r[d]) - rest.V.row(s[d])) / L(e);
      for (int c = 0; c < 3; ++c) dir[d][c] = static_cast<float>(u(c));
      len[d] = static_cast<float>(L(e));
    }
  }
  topo.corner_rows = face_corner_rows(topo.faces, n);
  topo.sender_rows = group_rows(topo.senders, n);
  topo.receiver_rows = group_rows(topo.receivers, n);
  Eigen::VectorXd area = vertex_masses(rest.V, rest.F, 1.0);
  Eigen::Index worst;
  // Log masses are features: every vertex needs a face of positive area.
  if (!(area.minCoeff(&worst) > 0))
    fail_file(where, "vertex " + std::to_string(worst) + " has no face of positive area");
  topo.vertex_area = to_float_tensor(area);
  topo.vertex_mean_edge_length = to_float_tensor(vertex_mean_edge_length(rest.V, rest.F));
  return topo;
}

GarmentTopology garment_topology_to(const GarmentTopology& topology, torch::Device device) {
  GarmentTopology out = topology;
  for (torch::Tensor* t : {&out.faces, &out.senders, &out.receivers, &out.rest_direction, &out.rest_length,
                           &out.vertex_area, &out.vertex_mean_edge_length})
    if (t->defined()) *t = t->to(device);
  // Groups serve CPU tensors only; elsewhere torch's kernels sum the rows.
  out.sender_rows = device.is_cpu() ? topology.sender_rows : RowIndex(out.senders);
  out.receiver_rows = device.is_cpu() ? topology.receiver_rows : RowIndex(out.receivers);
  out.corner_rows = device.is_cpu() ? topology.corner_rows : RowIndex();
  return out;
}

}  // namespace pb4u

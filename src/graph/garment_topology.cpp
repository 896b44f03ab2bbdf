#include "pb4u/graph/garment_topology.h"

#include "pb4u/graph/features.h"
#include "pb4u/mesh/coarse_levels.h"
#include "pb4u/mesh/edges.h"
#include "pb4u/mesh/geodesic_anchors.h"
#include "pb4u/mesh/geometry.h"
#include "pb4u/util/eigen_tensor.h"
#include "pb4u/util/error.h"

namespace pb4u {

namespace {
torch::Tensor to_float_tensor(const Eigen::VectorXd& v) {
  return torch::from_blob(const_cast<double*>(v.data()), {v.size()}, torch::kFloat64)
      .to(torch::kFloat32);
}

// The unique edges E (i, j) in both directions, (i -> j) first, with their rest geometry.
GarmentEdgeSet directed_edge_set(const Eigen::MatrixXd& rest, const Eigen::MatrixXi& E, int64_t n) {
  const int64_t ne = E.rows();
  GarmentEdgeSet set;
  set.senders = torch::empty({2 * ne}, torch::kInt64);
  set.receivers = torch::empty({2 * ne}, torch::kInt64);
  set.rest_direction = torch::empty({2 * ne, 3}, torch::kFloat32);
  set.rest_length = torch::empty({2 * ne}, torch::kFloat32);
  auto s = set.senders.accessor<int64_t, 1>(), r = set.receivers.accessor<int64_t, 1>();
  auto dir = set.rest_direction.accessor<float, 2>();
  auto len = set.rest_length.accessor<float, 1>();
  for (int64_t e = 0; e < ne; ++e) {
    const double length = (rest.row(E(e, 1)) - rest.row(E(e, 0))).norm();
    for (int64_t k = 0; k < 2; ++k) {
      const int64_t d = e + k * ne;
      s[d] = E(e, k);
      r[d] = E(e, 1 - k);
      // The mesh's edges have positive length (checked); a coarse edge between two vertices
      // that coincide gets no direction.
      Eigen::RowVector3d u = length > 0 ? Eigen::RowVector3d((rest.row(r[d]) - rest.row(s[d])) / length)
                                        : Eigen::RowVector3d::Zero();
      for (int c = 0; c < 3; ++c) dir[d][c] = static_cast<float>(u(c));
      len[d] = static_cast<float>(length);
    }
  }
  set.sender_rows = group_rows(set.senders, n);
  set.receiver_rows = group_rows(set.receivers, n);
  return set;
}
}  // namespace

GarmentTopology build_garment_topology(const TriMesh& rest, const std::string& where, int geodesic_anchor_count) {
  const int n = rest.num_vertices();
  if (rest.num_faces() == 0) fail_file(where, "garment mesh has no faces");
  if (rest.F.minCoeff() < 0 || rest.F.maxCoeff() >= n)
    fail_file(where, "face index out of range (mesh has " + std::to_string(n) + " vertices)");
  if (!rest.V.allFinite()) fail_file(where, "rest positions are not finite");

  Eigen::MatrixXi E = unique_edges(rest.F);
  Eigen::VectorXd L = edge_lengths(rest.V, E);
  if (L.minCoeff() <= 0) fail_file(where, "zero-length rest edge (weld or clean the mesh first)");

  GarmentTopology topo;
  topo.num_vertices = n;
  topo.mean_edge_length = L.mean();
  topo.faces = index_matrix_to_tensor(rest.F);

  GarmentEdgeSet mesh = directed_edge_set(rest.V, E, n);
  topo.senders = mesh.senders;
  topo.receivers = mesh.receivers;
  topo.sender_rows = mesh.sender_rows;
  topo.receiver_rows = mesh.receiver_rows;
  topo.rest_direction = mesh.rest_direction;
  topo.rest_length = mesh.rest_length;
  topo.corner_rows = face_corner_rows(topo.faces, n);
  CoarseLevels levels = coarse_levels(E, n, kCoarseLevels);
  for (const Eigen::MatrixXi& level : levels.edges) topo.coarse.push_back(directed_edge_set(rest.V, level, n));
  topo.vertex_level = torch::empty({n}, torch::kInt64);
  auto level_of = topo.vertex_level.accessor<int64_t, 1>();
  for (int v = 0; v < n; ++v) level_of[v] = levels.vertex_level(v);
  Eigen::VectorXd area = vertex_masses(rest.V, rest.F, 1.0);
  Eigen::Index worst;
  // Log masses are features: every vertex needs a face of positive area.
  if (!(area.minCoeff(&worst) > 0))
    fail_file(where, "vertex " + std::to_string(worst) + " has no face of positive area");
  topo.vertex_area = to_float_tensor(area);
  topo.vertex_mean_edge_length = to_float_tensor(vertex_mean_edge_length(rest.V, rest.F));
  if (geodesic_anchor_count > 0) {
    GeodesicAnchors geodesic = geodesic_anchors(E, L, n, geodesic_anchor_count);
    topo.anchors = torch::tensor(std::vector<int64_t>(geodesic.anchors.begin(), geodesic.anchors.end()), torch::kInt64);
    Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> d = geodesic.distance.cast<float>();
    topo.anchor_distance = torch::from_blob(d.data(), {d.rows(), d.cols()}, torch::kFloat32).clone();
  }
  return topo;
}

GarmentTopology garment_topology_to(const GarmentTopology& topology, torch::Device device) {
  GarmentTopology out = topology;
  for (torch::Tensor* t : {&out.faces, &out.senders, &out.receivers, &out.rest_direction, &out.rest_length,
                           &out.vertex_area, &out.vertex_mean_edge_length, &out.vertex_level, &out.anchors,
                           &out.anchor_distance})
    if (t->defined()) *t = t->to(device);
  for (GarmentEdgeSet& set : out.coarse) {
    for (torch::Tensor* t : {&set.senders, &set.receivers, &set.rest_direction, &set.rest_length})
      if (t->defined()) *t = t->to(device);
    if (!device.is_cpu()) {
      set.sender_rows = RowIndex(set.senders);
      set.receiver_rows = RowIndex(set.receivers);
    }
  }
  // Groups serve CPU tensors only; elsewhere torch's kernels sum the rows.
  out.sender_rows = device.is_cpu() ? topology.sender_rows : RowIndex(out.senders);
  out.receiver_rows = device.is_cpu() ? topology.receiver_rows : RowIndex(out.receivers);
  out.corner_rows = device.is_cpu() ? topology.corner_rows : RowIndex();
  return out;
}

}  // namespace pb4u

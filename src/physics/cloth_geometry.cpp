#include "pb4u/physics/cloth_geometry.h"

#include "pb4u/mesh/edges.h"
#include "pb4u/mesh/geometry.h"
#include "pb4u/mesh/rest_frames.h"
#include "pb4u/physics/bending_energy.h"
#include "pb4u/util/eigen_tensor.h"
#include "pb4u/util/error.h"

namespace pb4u {

ClothGeometry make_cloth_geometry(const TriMesh& rest, torch::Dtype dtype, torch::Device device,
                                  bool with_rest_angles, double degenerate_area) {
  const Eigen::MatrixXd& V = rest.V;
  const Eigen::MatrixXi& F = rest.F;
  if (V.rows() == 0 || F.rows() == 0 || V.cols() != 3 || F.cols() != 3)
    throw Error("cloth geometry: the garment mesh is empty");
  if (F.minCoeff() < 0 || F.maxCoeff() >= V.rows())
    throw Error("cloth geometry: face index out of range [0, " + std::to_string(V.rows()) + ")");
  if (!c10::isFloatingType(dtype)) throw Error("cloth geometry: the dtype must be floating point");
  if (!V.allFinite()) throw Error("cloth geometry: the garment mesh has non-finite vertices");

  ClothGeometry g;
  g.num_vertices = V.rows();
  g.faces = index_matrix_to_tensor(F);
  g.dm_inverse = matrix_to_tensor(rest_dm_inverse(V, F)).reshape({F.rows(), 2, 2});
  Eigen::VectorXd A = face_areas(V, F);
  g.face_area = matrix_to_tensor(A);
  g.face_area = g.face_area.reshape({F.rows()});
  g.vertex_area = matrix_to_tensor(vertex_masses(V, F, 1.0)).reshape({V.rows()});

  HingeSet h = interior_hinges(F);
  Eigen::MatrixXi H(h.size(), 4);
  Eigen::VectorXd w(h.size());
  for (int e = 0; e < h.size(); ++e) {
    H.row(e) << h.edge(e, 0), h.edge(e, 1), h.opposite(e, 0), h.opposite(e, 1);
    double l2 = (V.row(h.edge(e, 0)) - V.row(h.edge(e, 1))).squaredNorm();
    double a = A(h.faces(e, 0)) + A(h.faces(e, 1));
    w(e) = a > 0 ? l2 / (4.0 * a) : 0.0;  // a hinge between zero-area faces has no stiffness
  }
  g.hinges = h.size() ? index_matrix_to_tensor(H) : torch::zeros({0, 4}, torch::kInt64);
  g.hinge_weight = matrix_to_tensor(w).reshape({h.size()});
  g.rest_angle = with_rest_angles
                     ? dihedral_angles(matrix_to_tensor(V), g.hinges, degenerate_area)
                     : torch::zeros({h.size()}, torch::kFloat64);

  const Eigen::MatrixXi E = unique_edges(F);
  Eigen::VectorXd L(E.rows());
  for (Eigen::Index e = 0; e < E.rows(); ++e) L(e) = (V.row(E(e, 0)) - V.row(E(e, 1))).norm();
  g.edge_rest_length = matrix_to_tensor(L).reshape({E.rows()});

  auto opts = torch::TensorOptions().dtype(dtype).device(device);
  for (torch::Tensor* t : {&g.dm_inverse, &g.face_area, &g.vertex_area, &g.hinge_weight, &g.rest_angle,
                           &g.edge_rest_length})
    *t = t->to(opts);
  g.faces = g.faces.to(device);
  g.hinges = g.hinges.to(device);
  return g;
}

}  // namespace pb4u

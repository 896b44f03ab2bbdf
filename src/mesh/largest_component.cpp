#include "pb4u/mesh/largest_component.h"

#include <algorithm>
#include <vector>

#include "pb4u/mesh/clean.h"
#include "pb4u/mesh/topology.h"

namespace pb4u {

TriMesh largest_component(const TriMesh& mesh) {
  int count = 0;
  Eigen::VectorXi label = connected_components(mesh.F, mesh.num_vertices(), &count);
  if (count <= 1) return mesh;
  std::vector<int> faces_per(count, 0);
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) ++faces_per[label[mesh.F(f, 0)]];
  const int best = static_cast<int>(std::max_element(faces_per.begin(), faces_per.end()) -
                                    faces_per.begin());
  TriMesh out;
  out.V = mesh.V;
  out.F.resize(faces_per[best], 3);
  int n = 0;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    if (label[mesh.F(f, 0)] == best) out.F.row(n++) = mesh.F.row(f);
  remove_unreferenced_vertices(out);
  return out;
}

}  // namespace pb4u

#include "pb4u/io/mesh_summary.h"

#include <cstdio>

#include "pb4u/io/mesh_io.h"
#include "pb4u/mesh/edges.h"
#include "pb4u/mesh/geometry.h"
#include "pb4u/mesh/topology.h"

namespace pb4u {

MeshSummary summarize_mesh(const TriMesh& mesh) {
  MeshSummary s;
  s.vertices = mesh.num_vertices();
  s.faces = mesh.num_faces();
  s.edges = static_cast<int>(unique_edges(mesh.F).rows());
  connected_components(mesh.F, mesh.num_vertices(), &s.components);
  for (const auto& loop : boundary_loops(mesh.F))
    s.boundary_loop_sizes.push_back(static_cast<int>(loop.size()));
  ManifoldReport m = check_manifold(mesh.F, mesh.num_vertices());
  s.manifold = m.manifold();
  s.oriented = m.oriented();
  s.mean_edge_length = mean_edge_length(mesh.V, mesh.F);
  // Slivers: area below 1e-10 of the mean edge length squared.
  double sliver = 1e-10 * s.mean_edge_length * s.mean_edge_length;
  s.degenerate_faces = count_degenerate_faces(mesh.V, mesh.F, sliver);
  auto box = bounding_box(mesh.V);
  for (int k = 0; k < 3; ++k) {
    s.bbox_min[k] = box(0, k);
    s.bbox_max[k] = box(1, k);
  }
  return s;
}

MeshSummary summarize_mesh_file(const std::string& path) {
  CleanReport report;
  TriMesh mesh = read_mesh(path, {}, &report);
  MeshSummary s = summarize_mesh(mesh);
  s.degenerate_faces += report.removed_faces;
  return s;
}

void print_mesh_summary(std::ostream& out, const MeshSummary& s) {
  char buf[256];
  out << "vertices: " << s.vertices << "\n";
  out << "faces: " << s.faces << "\n";
  out << "edges: " << s.edges << "\n";
  out << "components: " << s.components << "\n";
  out << "boundary loops: " << s.boundary_loop_sizes.size();
  if (!s.boundary_loop_sizes.empty()) {
    out << " (vertices:";
    for (int n : s.boundary_loop_sizes) out << ' ' << n;
    out << ")";
  }
  out << "\n";
  out << "manifold: " << (s.manifold ? "yes" : "no") << "\n";
  out << "consistently oriented: " << (s.oriented ? "yes" : "no") << "\n";
  out << "degenerate faces: " << s.degenerate_faces << "\n";
  std::snprintf(buf, sizeof buf, "mean edge length: %.6g m\n", s.mean_edge_length);
  out << buf;
  std::snprintf(buf, sizeof buf, "bbox: min (%.4f, %.4f, %.4f) max (%.4f, %.4f, %.4f) m\n",
                s.bbox_min[0], s.bbox_min[1], s.bbox_min[2], s.bbox_max[0], s.bbox_max[1],
                s.bbox_max[2]);
  out << buf;
}

}  // namespace pb4u

// All CGAL code of the project lives here: it compiles slowly and needs -frounding-math.
#include "pb4u/mesh/remesh.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "pb4u/mesh/geometry.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

Mesh to_cgal(const TriMesh& in) {
  Mesh m;
  std::vector<Mesh::Vertex_index> vi(in.V.rows());
  for (Eigen::Index i = 0; i < in.V.rows(); ++i)
    vi[i] = m.add_vertex(Point(in.V(i, 0), in.V(i, 1), in.V(i, 2)));
  for (Eigen::Index f = 0; f < in.F.rows(); ++f) {
    auto face = m.add_face(vi[in.F(f, 0)], vi[in.F(f, 1)], vi[in.F(f, 2)]);
    if (face == Mesh::null_face())
      throw Error("remesh: face " + std::to_string(f) + " makes the mesh non-manifold");
  }
  return m;
}

TriMesh from_cgal(const Mesh& m) {
  TriMesh out;
  std::vector<int> index(m.num_vertices() + m.number_of_removed_vertices(), -1);
  out.V.resize(m.number_of_vertices(), 3);
  int n = 0;
  for (auto v : m.vertices()) {
    const Point& p = m.point(v);
    out.V.row(n) << p.x(), p.y(), p.z();
    index[v.idx()] = n++;
  }
  out.F.resize(m.number_of_faces(), 3);
  int f = 0;
  for (auto face : m.faces()) {
    int k = 0;
    for (auto v : CGAL::vertices_around_face(m.halfedge(face), m)) {
      if (k < 3) out.F(f, k) = index[v.idx()];
      ++k;
    }
    ++f;
  }
  return out;
}

// Remeshes a copy of `m`: long border edges split first so the border is sampled like the
// interior; border vertices then only move along the border.
Mesh remesh_copy(const Mesh& input, double edge_length, int iterations) {
  Mesh m = input;
  std::vector<Mesh::Halfedge_index> border;
  PMP::border_halfedges(faces(m), m, std::back_inserter(border));
  std::vector<Mesh::Edge_index> border_edges;
  for (auto h : border) border_edges.push_back(m.edge(h));
  if (!border_edges.empty()) PMP::split_long_edges(border_edges, edge_length, m);
  PMP::isotropic_remeshing(faces(m), edge_length, m,
                           CGAL::parameters::number_of_iterations(iterations)
                               .number_of_relaxation_steps(3));
  m.collect_garbage();
  return m;
}

void check_length(double edge_length) {
  if (!(edge_length > 0) || !std::isfinite(edge_length))
    throw Error("remesh: target edge length must be positive");
}

}  // namespace

TriMesh remesh_isotropic(const TriMesh& mesh, double edge_length, int iterations) {
  check_length(edge_length);
  if (mesh.F.rows() == 0) throw Error("remesh: empty mesh");
  return from_cgal(remesh_copy(to_cgal(mesh), edge_length, iterations));
}

double edge_length_for_triangles(double area, int triangles) {
  return std::sqrt(4.0 * area / (std::sqrt(3.0) * std::max(triangles, 1)));
}

TriMesh remesh_to_triangle_count(const TriMesh& mesh, int target_triangles, double tolerance,
                                 int max_attempts) {
  if (target_triangles < 4) throw Error("remesh: target triangle count must be at least 4");
  if (mesh.F.rows() == 0) throw Error("remesh: empty mesh");
  const double area = face_areas(mesh.V, mesh.F).sum();
  // Isotropic remeshing keeps edges in [4/5 L, 4/3 L], mostly below L, which gives ~22 %
  // more triangles than equilateral tiling at L.
  double length = 1.1 * edge_length_for_triangles(area, target_triangles);
  check_length(length);
  Mesh input = to_cgal(mesh);
  // A coarse input quantises the result (all edges split or none); remeshing it first to
  // well below the target length makes the triangle count a smooth function of L.
  if (mean_edge_length(mesh.V, mesh.F) > 0.5 * length) {
    std::vector<Mesh::Edge_index> all(input.edges().begin(), input.edges().end());
    PMP::split_long_edges(all, 0.5 * length, input);
    input = remesh_copy(input, 0.5 * length, 3);
  }
  TriMesh best;
  double best_error = 1e300;
  double lo = 0, hi = 1e300;  // lengths known to give too many / too few triangles
  for (int attempt = 0; attempt < max_attempts; ++attempt) {
    TriMesh out = from_cgal(remesh_copy(input, length, 5));
    const double ratio = static_cast<double>(out.num_faces()) / target_triangles;
    const double error = std::abs(ratio - 1.0);
    if (std::getenv("PB4U_DEBUG_REMESH"))
      std::fprintf(stderr, "remesh attempt %d: L=%g -> %d (target %d)\n", attempt, length,
                   out.num_faces(), target_triangles);
    if (error < best_error) best = std::move(out), best_error = error;
    if (error <= tolerance) break;
    (ratio > 1 ? lo : hi) = length;
    length *= std::sqrt(ratio);
    if (length <= lo || length >= hi) length = hi < 1e300 && lo > 0 ? std::sqrt(lo * hi) : length;
  }
  return best;
}

}  // namespace pb4u

#pragma once
// Isotropic remeshing (CGAL Polygon_mesh_processing::isotropic_remeshing) behind a plain
// Eigen interface. Vertices stay on the input surface; boundaries are kept (resampled to
// the target length) so open garments keep their outline.
#include "pb4u/mesh/triangle_mesh.h"

namespace pb4u {

// Remeshes to edges of about `edge_length` (m) with `iterations` split/collapse/flip/relax
// rounds. Throws pb4u::Error if the mesh is not a valid polygon mesh (non-manifold).
TriMesh remesh_isotropic(const TriMesh& mesh, double edge_length, int iterations = 5);

// Edge length (m) that tiles area `area` (m^2) with `triangles` equilateral triangles:
// L = sqrt(4 A / (sqrt(3) T)).
double edge_length_for_triangles(double area, int triangles);

// Remeshes to about `target_triangles` triangles: starts from edge_length_for_triangles and
// corrects the length by sqrt(T_obtained / T_target) until within `tolerance` (relative) or
// `max_attempts` runs; returns the closest result.
TriMesh remesh_to_triangle_count(const TriMesh& mesh, int target_triangles,
                                 double tolerance = 0.03, int max_attempts = 6);

}  // namespace pb4u

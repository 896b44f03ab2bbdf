#pragma once
// Isotropic remeshing (CGAL Polygon_mesh_processing::isotropic_remeshing) behind a plain
// Eigen interface. Vertices stay on the input surface; boundaries are kept (resampled to
// the target length) so open garments keep their outline.
#include "pb4u/mesh/triangle_mesh.h"

namespace pb4u {

// Remeshes to edges of about `edge_length` (m) with `iterations` split/collapse/flip/relax
// rounds. Throws pb4u::Error if the mesh is not a valid polygon mesh (non-manifold).
TriMesh remesh_isotropic(const TriMesh& mesh, double edge_length, int iterations = 3);

// Edge length (m) that tiles area `area` (m^2) with `triangles` equilateral triangles:
// L = sqrt(4 A / (sqrt(3) T)).
double edge_length_for_triangles(double area, int triangles);

// Remeshes to about `target_triangles` triangles: starts from edge_length_for_triangles and
// corrects the length by sqrt(T_obtained / T_target) until within `tolerance` (relative) or
// `max_attempts` runs; returns the closest result.
TriMesh remesh_to_triangle_count(const TriMesh& mesh, int target_triangles,
                                 double tolerance = 0.05, int max_attempts = 6);

// A remeshing source for targets up to `max_target_triangles`: a mesh much finer than that
// (e.g. straight from polygonisation) is first remeshed once to a quarter of the finest
// target's edge area (chord error ~ (L/2)^2 / 8r, far below the targets'), so repeated
// remeshing to each level costs little. Coarser meshes are returned unchanged.
TriMesh remesh_source_for(const TriMesh& mesh, int max_target_triangles);

}  // namespace pb4u

#pragma once
// Repairs applied to every imported mesh: welding, degenerate and unreferenced
// element removal, polygon triangulation.
#include <vector>

#include "pb4u/mesh/triangle_mesh.h"

namespace pb4u {

// Merges vertices closer than `relative_tolerance` times the bounding-box diagonal and
// remaps F. Returns the number of vertices removed. Unreferenced vertices are kept.
int weld_vertices(TriMesh& mesh, double relative_tolerance = 1e-6);

// Drops faces with a repeated vertex, with area below `min_area` (m^2), or duplicating
// another face (same vertex set). Returns the number of faces removed.
int remove_degenerate_faces(TriMesh& mesh, double min_area = 0.0);

// Drops vertices no face references and compacts indices. Returns the number removed.
int remove_unreferenced_vertices(TriMesh& mesh);

// Fan-triangulates polygons given as vertex-index lists (convex or nearly so, as exported
// by DCC tools). Polygons with fewer than 3 vertices are skipped.
Eigen::MatrixXi triangulate_polygons(const std::vector<std::vector<int>>& polygons);

struct CleanReport {
  int welded_vertices = 0, removed_faces = 0, removed_vertices = 0;
};

// weld_vertices, then remove_degenerate_faces, then remove_unreferenced_vertices.
CleanReport clean_mesh(TriMesh& mesh, double relative_weld_tolerance = 1e-6);

}  // namespace pb4u

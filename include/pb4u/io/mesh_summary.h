#pragma once
// What `pb4u inspect` says about a mesh file.
#include <ostream>
#include <string>
#include <vector>

#include "pb4u/mesh/triangle_mesh.h"

namespace pb4u {

struct MeshSummary {
  int vertices = 0, faces = 0, edges = 0, components = 0;
  std::vector<int> boundary_loop_sizes;  // vertices per loop
  bool manifold = false, oriented = false;
  int degenerate_faces = 0;  // removed on import (repeated vertex, zero area, duplicate) + slivers
  double mean_edge_length = 0;  // m
  double bbox_min[3] = {0, 0, 0}, bbox_max[3] = {0, 0, 0};
};

MeshSummary summarize_mesh(const TriMesh& mesh);
// Reads, cleans and summarises a mesh file (see read_mesh for the errors).
MeshSummary summarize_mesh_file(const std::string& path);

// One "name: value" per line, in the order of the struct.
void print_mesh_summary(std::ostream& out, const MeshSummary& s);

}  // namespace pb4u

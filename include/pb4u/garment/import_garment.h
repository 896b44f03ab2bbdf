#pragma once
// A user's garment file (OBJ, PLY, glTF, ...) as a simulation mesh at a target resolution.
#include <string>

#include "pb4u/mesh/triangle_mesh.h"

namespace pb4u {

// Reads, welds and cleans the file (read_mesh), then remeshes it isotropically to about
// `target_triangles`. Throws pb4u::Error naming `path` on unreadable or non-manifold input.
TriMesh import_garment(const std::string& path, int target_triangles);

}  // namespace pb4u

#pragma once
// Keeps the connected component with the most faces.
#include "pb4u/mesh/triangle_mesh.h"

namespace pb4u {

// The component (over shared vertices) with the most faces, unreferenced vertices dropped.
TriMesh largest_component(const TriMesh& mesh);

}  // namespace pb4u

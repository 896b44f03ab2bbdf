#pragma once
// Polygonisation of a sampled scalar field: the zero level set of its piecewise-linear
// interpolant over a Kuhn (6 tetrahedra per cube) subdivision of the grid. Unlike marching
// cubes there are no ambiguous cases: a field negative inside a region that stays clear of
// the grid's border gives a closed, consistently oriented 2-manifold.
#include <Eigen/Core>

#include "pb4u/body/implicit_body.h"
#include "pb4u/mesh/triangle_mesh.h"

namespace pb4u {

// values: grid.size() samples (see Grid). Triangles face towards increasing values
// (outwards for a negative-inside field). Vertices shared between cells are shared.
TriMesh marching_tetrahedra(const Grid& grid, const Eigen::VectorXd& values);

}  // namespace pb4u

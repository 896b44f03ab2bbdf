#pragma once
// The distance of every candidate pair (contact_candidates.h) with the rows of its four
// points, cloth points first: a cloth vertex and a body face's three vertices, or a cloth
// edge's two ends and a body edge's two ends. What the barrier, the carry and the freedom test
// all walk over.
#include <Eigen/Core>

#include <array>

#include "pb4u/physics/contact_candidates.h"
#include "pb4u/physics/primitive_distance.h"

namespace pb4u {

// visit(const PrimitiveDistance&, const std::array<int, 4>& points, int cloth_points) for each
// pair: points[0 .. cloth_points) index x, the rest body.V.
template <class Visit>
void for_each_pair_distance(const Eigen::MatrixXd& x, const Eigen::MatrixXi& cloth_edges, const ContactSurface& body,
                            const ContactCandidates& candidates, Visit&& visit) {
  for (const auto& [v, f] : candidates.vertex_face) {
    const std::array<int, 4> points{v, body.F(f, 0), body.F(f, 1), body.F(f, 2)};
    visit(point_triangle_distance(point_row(x, v), point_row(body.V, points[1]), point_row(body.V, points[2]),
                                  point_row(body.V, points[3])),
          points, 1);
  }
  for (const auto& [e, be] : candidates.edge_edge) {
    const std::array<int, 4> points{cloth_edges(e, 0), cloth_edges(e, 1), body.E(be, 0), body.E(be, 1)};
    visit(edge_edge_distance(point_row(x, points[0]), point_row(x, points[1]), point_row(body.V, points[2]),
                             point_row(body.V, points[3])),
          points, 2);
  }
}

}  // namespace pb4u

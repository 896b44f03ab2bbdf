#pragma once
// A garment's rest mesh made free of its body at the bind pose.
//
// A surface a few millimetres off the body, remeshed coarsely, is a polygon whose chords cut a
// curved body: four 7 cm edges round a 4 cm arm dip 5 mm into it. At its coarsest level the
// tiny dataset's t-shirt had 41 of its 321 edges through the mannequin at rest, and the quick
// dataset's imported t-shirt 232 (its straight sleeves pierced by the lowered arms). No
// intersection-free solver can start from such a garment, and pushing the posed cloth out of
// the body instead stretches it, since its rest lengths stay. Here the rest shape itself moves
// out, so the garment is a little wider where its mesh is too coarse to follow the body.
#include <Eigen/Core>

#include <string>

#include "pb4u/mesh/triangle_mesh.h"

namespace pb4u {

struct BodyClearance {
  int edges_through_before = 0;  // garment edges through the body as given
  int edges_through = 0;         // left after the rounds (0 unless max_rounds ran out)
  int vertices_inside = 0;       // left closer than the clearance (0 unless max_rounds ran out)
  int moved = 0;                 // garment vertices moved
  double largest_move = 0;       // m
  // Faces the moves turned over (their normal now points more than 90 degrees from where it
  // did): a garment that does not fit the body, cut round a limb that passes through its walls,
  // is folded where its vertices went out on either side of the limb.
  int folded_faces = 0;
  bool clear() const { return edges_through == 0 && vertices_inside == 0; }
};

// Moves the vertices of `garment` (rest shape at the bind pose, metres) until none is closer
// than `clearance` (m) to `body` (closed, outward; at the same pose) and no garment edge passes
// through it. Each round moves a vertex closer than the clearance to its closest body point
// plus the clearance outward, and both ends of each edge through the body out along the
// outward direction at the edge's deepest point, by that depth plus the clearance; a vertex on
// several such edges takes the largest move. A garment already clear is left exactly as it
// is. Faces, vertex order and count never change. As the solver's contact (cloth vertices
// against body faces, cloth edges against body edges), it does not look at body vertices
// against garment faces: a coarse face over a convex body part can still dip into it between
// its clear edges (the tiny skirt at level 1: 17 body edges through its faces at rest).
BodyClearance clear_of_body(TriMesh& garment, const TriMesh& body, double clearance, int max_rounds = 30);

// clear_of_body, and what it did logged under `label` (a file or a dataset's garment level):
// how far it moved the garment, and a warning where it folded faces (a garment that does not
// fit its body) or could not clear the garment. What generate and simulate run on a garment.
BodyClearance clear_of_body_logged(TriMesh& garment, const TriMesh& body, double clearance, const std::string& label);

}  // namespace pb4u

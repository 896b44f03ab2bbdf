#pragma once
// How far a garment is inside the body (SPEC 9 stability figures): the share of garment
// vertices inside the body surface and the deepest one, from exact signed distances
// (spatial/signed_distance_to_surface.h). A rollout measures x_{t+1} against the body at
// t + 1, the pose the frame must respect.
#include <Eigen/Core>
#include <vector>

namespace pb4u {

// One frame.
struct PenetrationFigures {
  double penetrating_fraction = 0;  // share of garment vertices with signed distance < 0
  double max_penetration_mm = 0;    // mm: depth of the deepest one; 0 when none is inside
  // Cloth edges through a body triangle (barrier_potential.h's cloth_edges_through_body): an
  // edge whose ends are both outside can still cut a limb. Set by the rollout; -1: not measured.
  int edges_through = -1;
  // Faces of the body inside another part of it (body/outer_faces.h's covered faces): > 0 where
  // the posed body crosses itself (a hand sunk into a hip), where cloth pinched between the two
  // parts has no intersection-free place.
  int body_self_crossing_faces = 0;
};

// garment: n x 3 (m); body_V: nb x 3 (m); body_F: mb x 3, closed and outward. Counts the body's
// self-crossing faces on every call (a few ms for a 6K-face body). Vertices outside
// the body's bounding box are outside a closed body and are not measured further. Throws
// pb4u::Error on non-finite input or an empty garment or body.
PenetrationFigures garment_penetration(const Eigen::MatrixXd& garment, const Eigen::MatrixXd& body_V,
                                       const Eigen::MatrixXi& body_F);

// Frames (or sequences) summarised.
struct PenetrationSummary {
  double penetrating_fraction = 0;      // mean over frames of the penetrating fraction
  double max_penetrating_fraction = 0;  // its largest value on a frame
  double max_penetration_mm = 0;        // mm: the deepest penetration on any frame
  int max_edges_through = -1;           // most cloth edges through the body on a frame (-1: not measured)
  int frames_with_edges_through = 0;    // frames with at least one
  int frames = 0;                       // frames summarised
  int max_body_self_crossing_faces = 0;  // most body faces inside another part of it on a frame
  int frames_with_body_self_crossing = 0;  // frames where the body crosses itself
};

// Over the frames of a sequence. Throws pb4u::Error when empty.
PenetrationSummary summarize_penetration(const std::vector<PenetrationFigures>& frames);
// Over sequences: the mean of their means (as the energies: frames, then sequences) and the
// largest maxima. Throws pb4u::Error when empty.
PenetrationSummary summarize_penetration(const std::vector<PenetrationSummary>& sequences);

}  // namespace pb4u

#pragma once
// Skinning weights for a garment: copied from the nearest body vertex where the garment lies
// on the body, inpainted over the garment surface where it stands off it, then smoothed, so
// that neighbouring garment vertices never follow different bones abruptly (a skirt between
// the legs would otherwise tear under LBS).
#include <Eigen/Core>
#include <vector>

#include "pb4u/body/body.h"
#include "pb4u/mesh/triangle_mesh.h"

namespace pb4u {

// V: n x 3 garment positions around body's bind pose (m). Returns n x J weights, each row the
// weights of the nearest body vertex.
Eigen::MatrixXd transfer_skin_weights(const Eigen::MatrixXd& V, const Body& body);

// W (n x J) diffused over the mesh's edge graph for a length of about `length` m whatever the
// resolution: Jacobi steps W_i <- (W_i + mean of the neighbours' W) / 2, (length / Lbar)^2 * 2 of
// them (a random walk of that many half-steps of the mean edge length Lbar spreads ~length).
// Rows still sum to 1. length <= 0 returns W unchanged.
Eigen::MatrixXd smooth_skin_weights(const TriMesh& mesh, const Eigen::MatrixXd& W, double length);

// W with the rows not `known` replaced by the harmonic interpolation of the known ones over
// the mesh's edge graph (each such row the mean of its neighbours): weight inpainting, as in
// robust skin-weight transfer. Rows still sum to 1.
Eigen::MatrixXd inpaint_skin_weights(const TriMesh& mesh, const Eigen::MatrixXd& W,
                                     const std::vector<bool>& known);

// What garments get: nearest-body-vertex weights where the garment is within
// `inpaint_distance` m of the body at the bind pose, inpainted where it is farther (the flare
// of a skirt between the legs follows both legs and the hips, not one leg), then smoothed
// over `smoothing_length` m. inpaint_distance <= 0: every vertex keeps its nearest weights.
struct SkinWeightOptions {
  double smoothing = 0.1;          // m, smooth_skin_weights' length
  double inpaint_distance = 0.03;  // m
};
Eigen::MatrixXd garment_skin_weights(const TriMesh& mesh, const Body& body, const SkinWeightOptions& options);

}  // namespace pb4u

#pragma once
// LBS-initialised frames: the training input of SPEC 4/5. For frame t of a motion the body
// at t-1, t, t+1 and the garment at t-1, t, posed by linear blend skinning with the
// garment's transferred weights; garment vertices that end up inside (or closer than `gap`
// to) the body are pushed out along the nearest body face normal, a cheap pre-solve.
#include <Eigen/Core>

#include "pb4u/body/body.h"
#include "pb4u/garment/garment.h"

namespace pb4u {

struct LbsFrame {
  Eigen::MatrixXd garment_prev, garment;    // n x 3 (m), at t - 1 and t
  Eigen::MatrixXd body_prev, body, body_next;  // nb x 3 (m), at t - 1, t, t + 1
};

// Moves each row of X whose signed distance to the nearest body face (by centroid) is
// below `gap` (m) along that face's outward normal to distance `gap`. body_V: nb x 3,
// body_F: mb x 3, outward-oriented. Returns the number of vertices moved.
int push_out_of_body(Eigen::MatrixXd& X, const Eigen::MatrixXd& body_V,
                     const Eigen::MatrixXi& body_F, double gap);

// Frame t (clamped to the motion; t - 1 and t + 1 are clamped too).
LbsFrame lbs_frame(const Body& body, const Garment& garment, const Motion& motion, int t,
                   double gap);

// The garment alone at frame t (clamped), skinned and pushed out of `posed_body` (the body
// at that frame).
Eigen::MatrixXd lbs_garment(const Body& body, const Garment& garment, const Motion& motion, int t,
                            const Eigen::MatrixXd& posed_body, double gap);

}  // namespace pb4u

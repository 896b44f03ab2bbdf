#pragma once
// A garment's first frame reached by the intersection-free solver from its rest shape, instead
// of by skinning alone.
//
// A skinned start (data/lbs_frame.h) poses the garment with weights smoothed over 10 cm, which
// differ from the body's own near the joints: on the tiny dataset's spin its first frame has 16
// coarse t-shirt edges through the mannequin's shoulders and arms, on the jump's crouch cloth
// up to 5 cm inside, where no push out of the posed body finds a free place
// (physics/intersection_free_start.h). Here the body moves from its bind pose, where the rest
// mesh is free of it (garment/clear_of_body.h), to the motion's first pose in `steps` steps
// (rotations by slerp, the root linearly). Each step the reference solver (barrier contact; CCD
// on the body's move) advances the cloth with the velocity skinning would give it, without
// gravity or friction: the cloth follows the skinning where the body leaves room and is pushed
// where it does not, so it is never inside the body. Each step runs first with the body carrying
// the cloth it meets (solver.release_held_cloth off) and, where that leaves cloth through the body
// or out of barrier contact, again with the release on; the one with fewer cloth edges through the
// body, then fewer vertices inside, is kept. It then starts with the velocity skinning gives it
// from the first pose to the next (the body is already moving there).
#include <Eigen/Core>

#include <string>
#include <vector>

#include "pb4u/body/body.h"
#include "pb4u/garment/garment.h"
#include "pb4u/physics/physics_config.h"
#include "pb4u/scene/material.h"

namespace pb4u {

struct SettledStart {
  Eigen::MatrixXd x;         // n x 3 m: the garment at the first pose
  Eigen::MatrixXd x_prev;    // n x 3 m: one frame before, x minus the skinned motion to the next pose
  int excluded_max = 0;      // the most vertices a step left out of barrier contact
  int edges_through = 0;     // cloth edges through the body at the first pose
  double inside_fraction = 0;  // share of the cloth vertices inside the body at the first pose
  double seconds = 0;        // wall time of the steps
};

// `first`, `next`: the motion's first pose and the one after it; steps >= 1. pinned: vertices held on the body (a
// waistband), which follow the skinned garment pushed `push_out_gap` m out of each step's body
// and are kept where no edge between two of them cuts it. Throws pb4u::Error if the garment has
// no skinning weights.
SettledStart settled_start(const Body& body, const Garment& garment, const Pose& first, const Pose& next, int steps,
                           const Material& material, const std::vector<int>& pinned, double push_out_gap,
                           const PhysicsConfig& physics);

// A rollout's frame 0 and the frame before it from `st`: the settled cloth, the vertices in
// `riding` (pins that rode on the body) set to frame 0's `pin_targets` rows, and x_prev behind x0
// by the skinned motion to the next pose. `pin_targets` is read only when `riding` is not empty.
void settled_rollout_start(const SettledStart& st, const std::vector<int>& riding, const Eigen::MatrixXd& pin_targets,
                           Eigen::MatrixXd* x0, Eigen::MatrixXd* x_prev);

// One line for the log: the steps, their time and what the start left through the body.
std::string describe_settled_start(const SettledStart& st, int steps);

}  // namespace pb4u

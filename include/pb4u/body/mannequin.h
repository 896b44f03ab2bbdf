#pragma once
// A mannequin for any humanoid skeleton: tapered capsules along its bones in the bind pose
// (humanoid_bind_pose), smoothly united, polygonised and remeshed. Closed, outward, genus 0,
// free of self-intersections by construction; feet at y = 0, facing +z.
#include <string>

#include "pb4u/body/body.h"
#include "pb4u/body/humanoid.h"
#include "pb4u/body/implicit_body.h"
#include "pb4u/config/config_io.h"

namespace pb4u {

// Body part sizes as fractions of the stature, estimated from the skeleton
// (head joint to ankle distance / head_to_ankle_fraction).
struct MannequinProportions {
  double head_to_ankle_fraction = 0.86;
  double head_radius = 0.062, head_lift = 0.05;  // head centre above the head joint
  double neck_radius = 0.032;
  double chest_half_width = 0.05, chest_radius = 0.058;
  double waist_half_width = 0.04, waist_radius = 0.05;
  double pelvis_half_width = 0.045, pelvis_radius = 0.056, pelvis_drop = 0.02;
  double collar_radius = 0.03;
  double upper_arm_radius = 0.026, elbow_radius = 0.021, wrist_radius = 0.016;
  double hand_length = 0.1, hand_radius = 0.014;
  double thigh_radius = 0.05, knee_radius = 0.032, ankle_radius = 0.021;
  double foot_radius = 0.02, toe_length = 0.035, toe_radius = 0.015;

  template <class V>
  void visit(V& v) {
    v("head_to_ankle_fraction", head_to_ankle_fraction, in_range(0.5, 1.0));
    for (auto& [key, field] : std::initializer_list<std::pair<const char*, double*>>{
             {"head_radius", &head_radius}, {"head_lift", &head_lift},
             {"neck_radius", &neck_radius}, {"chest_half_width", &chest_half_width},
             {"chest_radius", &chest_radius}, {"waist_half_width", &waist_half_width},
             {"waist_radius", &waist_radius}, {"pelvis_half_width", &pelvis_half_width},
             {"pelvis_radius", &pelvis_radius}, {"pelvis_drop", &pelvis_drop},
             {"collar_radius", &collar_radius}, {"upper_arm_radius", &upper_arm_radius},
             {"elbow_radius", &elbow_radius}, {"wrist_radius", &wrist_radius},
             {"hand_length", &hand_length}, {"hand_radius", &hand_radius},
             {"thigh_radius", &thigh_radius}, {"knee_radius", &knee_radius},
             {"ankle_radius", &ankle_radius}, {"foot_radius", &foot_radius},
             {"toe_length", &toe_length}, {"toe_radius", &toe_radius}})
      v(key, *field, in_range(0.0, 0.5));
  }
};

struct MannequinConfig {
  int vertices = 7000;          // target vertex count (triangles = 2 V - 4, genus 0)
  double cell_size = 0.006;     // m, polygonisation grid spacing (before remeshing)
  double blend = 0.02;          // fraction of stature: smooth-union width between parts
  double weight_falloff = 0.012;  // fraction of stature: skinning weight blend distance
  int max_influences = 4;       // joints per vertex
  double arm_angle_deg = 45.0;  // bind pose: arms from straight down (A-pose)
  double leg_angle_deg = 4.0;   // bind pose: legs from straight down
  MannequinProportions proportions;

  template <class V>
  void visit(V& v) {
    v("vertices", vertices, int_at_least(50));
    v("cell_size", cell_size, in_range(1e-3, 0.05));
    v("blend", blend, in_range(0.0, 0.1));
    v("weight_falloff", weight_falloff, in_range(1e-4, 0.2));
    v("max_influences", max_influences, int_in_range(1, 8));
    v("arm_angle_deg", arm_angle_deg, in_range(20.0, 90.0));
    v("leg_angle_deg", leg_angle_deg, in_range(0.0, 20.0));
    v("proportions", proportions);
  }
};

// The implicit solid of a humanoid in `bind` (root at the origin) and its stature (m).
ImplicitBody humanoid_implicit(const Skeleton& skeleton, const HumanoidJoints& joints,
                               const Pose& bind, const MannequinConfig& config,
                               double* stature = nullptr);

// Builds the mannequin. The bind pose's root is lifted so that the soles touch y = 0.
// Throws pb4u::Error naming `name` if the skeleton is not humanoid.
Body build_mannequin(const std::string& name, const Skeleton& skeleton,
                     const MannequinConfig& config = {});

// The implicit solid of a built mannequin, in its bind pose (feet at y = 0): the surface
// garment templates are offset from.
ImplicitBody mannequin_implicit(const Body& body, const MannequinConfig& config);

// n x J skinning weights from distances to the capsules of each joint:
// w_j ~ exp(-(d_j - d_min) / falloff), truncated to `max_influences` and normalised.
Eigen::MatrixXd capsule_skin_weights(const Eigen::MatrixXd& V, const ImplicitBody& body,
                                     int num_joints, double falloff, int max_influences);

}  // namespace pb4u

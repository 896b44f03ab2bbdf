#pragma once
// A skinned body: its surface at the bind pose, the skeleton that moves it and the weights.
#include <Eigen/Core>
#include <string>

#include "pb4u/body/skeleton.h"
#include "pb4u/mesh/triangle_mesh.h"

namespace pb4u {

struct Body {
  std::string name;
  TriMesh mesh;               // bind pose, metres, closed and outward-oriented
  Eigen::MatrixXd weights;    // n x J skinning weights, rows sum to 1
  Skeleton skeleton;
  Pose bind;                  // the pose `mesh` was built in (skinning_transforms' `bind`)
};

// The body's vertices (n x 3, m) at `pose` by linear blend skinning.
Eigen::MatrixXd pose_body(const Body& body, const Pose& pose);

}  // namespace pb4u

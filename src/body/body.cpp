#include "pb4u/body/body.h"

#include "pb4u/body/forward_kinematics.h"
#include "pb4u/body/linear_blend_skinning.h"

namespace pb4u {

Eigen::MatrixXd pose_body(const Body& body, const Pose& pose) {
  return linear_blend_skinning(body.mesh.V, body.weights,
                               skinning_transforms(body.skeleton, body.bind, pose));
}

}  // namespace pb4u

#include "pb4u/data/lbs_frame.h"

#include <algorithm>

#include "pb4u/body/linear_blend_skinning.h"
#include "pb4u/mesh/geometry.h"
#include "pb4u/spatial/point_kd_tree.h"
#include "pb4u/util/error.h"

namespace pb4u {

int push_out_of_body(Eigen::MatrixXd& X, const Eigen::MatrixXd& body_V,
                     const Eigen::MatrixXi& body_F, double gap) {
  const Eigen::MatrixXd N = face_normals(body_V, body_F);
  Eigen::MatrixXd C(body_F.rows(), 3);
  for (Eigen::Index f = 0; f < body_F.rows(); ++f)
    C.row(f) = (body_V.row(body_F(f, 0)) + body_V.row(body_F(f, 1)) + body_V.row(body_F(f, 2))) / 3.0;
  PointKdTree tree(C);
  Eigen::VectorXi nearest;
  tree.nearest(X, &nearest);
  int moved = 0;
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    const int f = nearest[i];
    if (f < 0) continue;
    const double d = (X.row(i) - C.row(f)).dot(N.row(f));
    if (d < gap) {
      X.row(i) += (gap - d) * N.row(f);
      ++moved;
    }
  }
  return moved;
}

Eigen::MatrixXd lbs_garment(const Body& body, const Garment& garment, const Motion& motion, int t,
                            const Eigen::MatrixXd& posed_body, double gap) {
  const int T = motion.num_frames();
  if (T == 0) throw Error("lbs_frame: empty motion");
  Eigen::MatrixXd X = linear_blend_skinning(
      garment.mesh.V, garment.weights,
      skinning_transforms(body.skeleton, body.bind, motion.frames[std::clamp(t, 0, T - 1)]));
  push_out_of_body(X, posed_body, body.mesh.F, gap);
  return X;
}

LbsFrame lbs_frame(const Body& body, const Garment& garment, const Motion& motion, int t,
                   double gap) {
  const int T = motion.num_frames();
  if (T == 0) throw Error("lbs_frame: empty motion");
  if (garment.weights.cols() != body.weights.cols())
    throw Error("lbs_frame: garment '" + garment.name + "' has weights for " +
                std::to_string(garment.weights.cols()) + " joints, body '" + body.name + "' has " +
                std::to_string(body.weights.cols()));
  auto frame = [&](int k) { return std::clamp(k, 0, T - 1); };
  auto body_at = [&](int k) { return pose_body(body, motion.frames[frame(k)]); };
  LbsFrame out;
  out.body_prev = body_at(t - 1);
  out.body = body_at(t);
  out.body_next = body_at(t + 1);
  out.garment_prev = lbs_garment(body, garment, motion, t - 1, out.body_prev, gap);
  out.garment = lbs_garment(body, garment, motion, t, out.body, gap);
  return out;
}

}  // namespace pb4u

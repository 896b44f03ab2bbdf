#include "pb4u/body/procedural_motion.h"

#include <algorithm>
#include <cmath>

#include "pb4u/util/error.h"

namespace pb4u {

const std::vector<std::string>& procedural_motion_names() {
  static const std::vector<std::string> names = {"walk",      "run",         "jump",
                                                 "arm_raise", "torso_twist", "spin"};
  return names;
}

MotionParams random_motion_params(const std::string& kind, int frames, const MotionRanges& r,
                                  std::mt19937& rng) {
  auto draw = [&](const std::vector<double>& range, const char* key) {
    if (range.size() != 2 || !(range[0] <= range[1]))
      throw Error(std::string("motion ranges: ") + key + " must be [min, max]");
    return std::uniform_real_distribution<double>(range[0], range[1])(rng);
  };
  MotionParams p;
  p.kind = kind;
  p.frames = frames;
  p.speed = draw(r.speed, "speed");
  p.amplitude = draw(r.amplitude, "amplitude");
  p.phase = std::uniform_real_distribution<double>(0.0, 1.0)(rng);
  return p;
}

namespace {

constexpr double kDeg = M_PI / 180.0;

Eigen::Quaterniond axis_angle(double deg, const Eigen::Vector3d& axis) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(deg * kDeg, axis));
}
const Eigen::Vector3d X = Eigen::Vector3d::UnitX(), Y = Eigen::Vector3d::UnitY(),
                      Z = Eigen::Vector3d::UnitZ();

// Per-frame joint-angle offsets (degrees, in each joint's bind frame) and root motion.
struct Offsets {
  double thigh[2] = {0, 0}, knee[2] = {0, 0}, arm_swing[2] = {0, 0}, arm_raise[2] = {0, 0};
  double elbow[2] = {0, 0}, spine_twist = 0, lean = 0, yaw = 0;
  Eigen::Vector3d root = Eigen::Vector3d::Zero();  // m, added to the bind root
};

Offsets offsets_at(const MotionParams& p, double t) {
  Offsets o;
  const double a = p.amplitude, s = p.speed;
  // Arms come down from the bind A-pose for locomotion.
  const double arms_down = -35.0;
  if (p.kind == "walk" || p.kind == "run") {
    const bool run = p.kind == "run";
    const double cadence = (run ? 1.4 : 0.9) * s;  // strides per second
    const double w = 2 * M_PI * cadence * t;
    const double hip = (run ? 40.0 : 25.0) * a, knee = (run ? 80.0 : 35.0) * a;
    for (int k = 0; k < 2; ++k) {
      const double ph = w + (k == 0 ? 0.0 : M_PI);
      o.thigh[k] = -hip * std::sin(ph);
      o.knee[k] = knee * std::max(0.0, std::sin(ph - 0.5 * M_PI));
      o.arm_swing[k] = -(run ? 30.0 : 15.0) * a * std::sin(ph);  // opposite to the leg
      o.arm_raise[k] = arms_down;
      o.elbow[k] = run ? 70.0 : 15.0;
    }
    o.lean = run ? 10.0 : 2.0;
    const double speed_m_s = (run ? 3.0 : 1.2) * s * std::min(a, 1.5);
    o.root = Eigen::Vector3d(0, (run ? 0.04 : 0.015) * a * std::abs(std::sin(w)), speed_m_s * t);
  } else if (p.kind == "jump") {
    const double period = 1.2 / s;
    const double u = std::fmod(t, period) / period;  // 0..1 in the cycle
    const double crouch = u < 0.35 ? std::sin(u / 0.35 * M_PI) : 0.0;
    const double air = u >= 0.35 && u < 0.75 ? (u - 0.35) / 0.4 : -1.0;
    for (int k = 0; k < 2; ++k) {
      o.thigh[k] = -50.0 * a * crouch;
      o.knee[k] = 90.0 * a * crouch;
      o.arm_swing[k] = 60.0 * a * (air >= 0 ? std::sin(air * M_PI) : -0.5 * crouch);
      o.arm_raise[k] = arms_down;
    }
    o.lean = 20.0 * a * crouch;
    const double height = 0.3 * a;
    o.root.y() = air >= 0 ? 4 * height * air * (1 - air) : -0.18 * a * crouch;
  } else if (p.kind == "arm_raise") {
    const double w = 2 * M_PI * 0.4 * s * t;
    for (int k = 0; k < 2; ++k) {
      o.arm_raise[k] = arms_down + (120.0 * a) * 0.5 * (1 - std::cos(w + (k == 0 ? 0 : 0.3)));
      o.elbow[k] = 10.0 * a * (1 - std::cos(w));
    }
  } else if (p.kind == "torso_twist") {
    const double w = 2 * M_PI * 0.5 * s * t;
    o.spine_twist = 35.0 * a * std::sin(w);
    for (int k = 0; k < 2; ++k) {
      o.arm_raise[k] = arms_down * 0.5;
      o.arm_swing[k] = 20.0 * a * std::sin(w) * (k == 0 ? 1 : -1);
    }
  } else if (p.kind == "spin") {
    o.yaw = 360.0 * 0.5 * s * t;  // half a turn per second at speed 1
    for (int k = 0; k < 2; ++k) o.arm_raise[k] = 25.0 * a;
    o.root.y() = 0.01 * a * std::sin(2 * M_PI * s * t);
  } else {
    throw Error("motion kind '" + p.kind +
                "': unknown (walk, run, jump, arm_raise, torso_twist, spin)");
  }
  return o;
}

}  // namespace

Motion procedural_motion(const Skeleton& skeleton, const Pose& bind, const MotionParams& params) {
  if (params.frames < 1) throw Error("motion '" + params.kind + "': frames must be >= 1");
  if (!(params.fps > 0)) throw Error("motion '" + params.kind + "': fps must be positive");
  const HumanoidJoints h = find_humanoid_joints(skeleton, "motion '" + params.kind + "'");
  Motion motion;
  motion.fps = params.fps;
  const int spine_joints = std::max<int>(1, static_cast<int>(h.torso.size()) - 1);
  for (int f = 0; f < params.frames; ++f) {
    const double t = f / params.fps + params.phase;
    const Offsets o = offsets_at(params, t);
    Pose pose = bind;
    auto apply = [&](int j, const Eigen::Quaterniond& delta) {
      pose.rotations[j] = (pose.rotations[j] * delta).normalized();
    };
    const Eigen::Quaterniond heading = axis_angle(o.yaw, Y);
    pose.rotations[h.root] = (heading * bind.rotations[h.root] * axis_angle(o.lean, X)).normalized();
    pose.root = bind.root + heading * o.root;
    for (size_t i = 1; i < h.torso.size(); ++i) apply(h.torso[i], axis_angle(o.spine_twist / spine_joints, Y));
    for (int k = 0; k < 2; ++k) {
      const double side = k == 0 ? 1.0 : -1.0;
      // The legs counter the torso lean so the feet stay under the body.
      apply(h.thigh[k], axis_angle(o.thigh[k] - o.lean, X));
      apply(h.knee[k], axis_angle(o.knee[k], X));
      apply(h.upper_arm[k], axis_angle(side * o.arm_raise[k], Z) * axis_angle(-o.arm_swing[k], X));
      apply(h.elbow[k], axis_angle(-o.elbow[k], X));
    }
    motion.frames.push_back(std::move(pose));
  }
  return motion;
}

}  // namespace pb4u

#pragma once
// Built-in motions for any humanoid skeleton (walk, run, jump, arm raise, torso twist,
// spin), expressed as rotations on top of the bind pose so they read the same on every body.
#include <random>
#include <string>
#include <vector>

#include "pb4u/body/humanoid.h"
#include "pb4u/body/skeleton.h"
#include "pb4u/config/config_io.h"

namespace pb4u {

// "walk", "run", "jump", "arm_raise", "torso_twist", "spin".
const std::vector<std::string>& procedural_motion_names();

struct MotionParams {
  std::string kind = "walk";
  double speed = 1.0;      // tempo multiplier (1 = a natural pace)
  double amplitude = 1.0;  // joint-angle / height multiplier
  double phase = 0.0;      // s, time offset into the cycle
  int frames = 90;
  double fps = 30.0;
};

// Ranges random_motion_params draws from (uniform).
struct MotionRanges {
  std::vector<double> speed = {0.7, 1.4};
  std::vector<double> amplitude = {0.6, 1.3};

  template <class V>
  void visit(V& v) {
    v("speed", speed);
    v("amplitude", amplitude);
  }
};

MotionParams random_motion_params(const std::string& kind, int frames, const MotionRanges& ranges,
                                  std::mt19937& rng);

// The motion of `params` on `skeleton` bound at `bind` (whose root translation places the
// body; the motion starts there). Throws pb4u::Error on an unknown kind.
Motion procedural_motion(const Skeleton& skeleton, const Pose& bind, const MotionParams& params);

}  // namespace pb4u

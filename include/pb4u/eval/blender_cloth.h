#pragma once
// Blender's cloth as a bench method: a rollout's garment, body motion, material and pins
// handed to scripts/blender_cloth.py under `blender -b`, its frames and per-frame solve times
// read back (the physics loss is then scored with pb4u's own terms, eval/score.h).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "pb4u/config/config_io.h"

namespace pb4u {

struct RolloutInput;  // eval/rollout.h

// YAML section `blender` of bench configs.
struct BlenderConfig {
  std::string enabled = "auto";  // auto: when the executable is found | on: required | off
  std::string executable = "blender";
  std::vector<int> qualities{5};  // Blender's cloth steps per frame, one bench row each
  double collision_distance = 0.005;  // m, cloth and body collision distance
  template <class V>
  void visit(V& v) {
    v("enabled", enabled, one_of({"auto", "on", "off"}));
    v("executable", executable);
    v("qualities", qualities);
    v("collision_distance", collision_distance, in_range(1e-4, 0.1));
  }
};

// The executable's full path ("" when not found): a path is checked as given, a bare name
// looked up on PATH.
std::string find_blender(const std::string& executable);

struct BlenderRollout {
  std::vector<Eigen::MatrixXd> frames;  // frames 0..steps, n x 3 m (frame 0: the start)
  std::vector<double> frame_ms;         // wall time of each frame's solve, frames 1..steps
};

// Runs Blender's cloth on `input` (its rest shape, start frame, body frames, material, pins;
// the cloth starts at rest) with `quality` steps per frame and `threads` threads (Blender's
// -t; the bench passes its own torch thread count so both sides get the same cores) in
// `work_dir` (created; its files are left for inspection). Throws pb4u::Error naming
// Blender's log on a failed run.
BlenderRollout run_blender_cloth(const RolloutInput& input, const std::string& blender, int quality, int threads,
                                 double collision_distance, const std::string& work_dir);

}  // namespace pb4u

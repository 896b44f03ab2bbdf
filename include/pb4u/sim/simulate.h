#pragma once
// `pb4u simulate`: a scene rolled out by the network or the reference solver, every frame
// written (OBJ/PLY per frame, PC2 caches, HDF5, energies CSV) and a Figure-3-style plot.
#include <string>
#include <vector>

#include "pb4u/model/model_file.h"
#include "pb4u/rollout/rollout.h"
#include "pb4u/sim/scene.h"

namespace pb4u {

struct SimulateResult {
  int frames = 0;                  // frames written (the start frame 0 included)
  bool diverged = false;
  int diverged_at_frame = -1;
  std::string diverged_reason;     // RolloutResult::diverged_reason
  int worst_vertex = -1;
  std::vector<std::string> files;  // everything written
  // Per-sequence figures over the measured frames (1..): positive energy (J), with a body the
  // share of garment vertices inside it, and the stepper's wall time per frame (ms).
  double positive_mean = 0, positive_max = 0;
  bool with_body = false;
  double penetrating_mean = 0, penetrating_max = 0, deepest_mm = 0;
  int edges_through_max = 0, edges_through_frames = 0;  // cloth edges through the body: most on a frame, frames with any
  // Frames where the body crosses itself, and most of its faces inside another part on one.
  int body_self_crossing_frames = 0, body_self_crossing_max = 0;
  double step_ms_mean = 0;
  // EnergyReport::residual_mm over the frames: the median reads the typical frame, the mean and
  // the largest what a rare frame far from its minimum adds.
  double residual_mm_median = 0, residual_mm_mean = 0, residual_mm_max = 0;
  bool residual_measured = true;                      // false with outputs.residual off
  // outputs.minimum_every: the sampled frames, and over them the median and largest distance to
  // the minimum (mm) and the median energy gap (J).
  MinimumSummary minimum;
  int own_start_frames = 0;  // refined frames started from the solver's own start (RolloutResult)
  // The intersection-free reference solver (solver.contact = barrier, with a body): frames that
  // left cloth out of barrier contact, and the most vertices one frame left out.
  bool barrier_contact = false;
  int excluded_frames = 0, excluded_max = 0;
  std::vector<std::string> terms;  // the energy terms (energies.csv also has total, residual_mm,
                                   // with a body penetrating_fraction and max_penetration_mm, and
                                   // with barrier_contact contact_excluded, caught_by_body, body_lag_mm)
};

// What a rollout of the built scene starts from: garment, body frames, pins, effects, the
// scene's material (also the metric material) and its frame count.
RolloutInput scene_rollout_input(const SceneConfig& scene, const SceneSetup& setup);

// Rolls `scene` out into `out_dir` (created if needed). model: null for the reference
// solver. A divergence (non-finite, or the scene's `divergence` energy guard) stops the
// rollout and keeps the frames written so far (reported in the result, not thrown). Throws
// pb4u::Error on a bad scene.
SimulateResult simulate(const SceneConfig& scene, const std::string& scene_path, const ModelFile* model,
                        const std::string& out_dir);

}  // namespace pb4u

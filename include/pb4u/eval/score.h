#pragma once
// `pb4u score`: the SPEC 3 terms of a cloth sequence made by any tool (pb4u, Blender, ...),
// frame by frame, with the code `evaluate` and `simulate` measure with (run_rollout's
// energies, the body penetration figures), and their per-sequence summary.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "pb4u/config/config_io.h"
#include "pb4u/mesh/triangle_mesh.h"
#include "pb4u/physics/energy_report.h"
#include "pb4u/scene/material.h"
#include "pb4u/physics/penetration.h"
#include "pb4u/physics/physics_config.h"
#include "pb4u/scene/effects.h"

namespace pb4u {

// What the scoring measures under, when no scene supplies it (`pb4u score --config/--set`).
struct ScoreConfig {
  // Active effects; [auto]: gravity, plus collision and friction when a body is given.
  std::vector<std::string> effects{"auto"};
  Material material;      // the cloth's material (also the one the energies are reported under)
  PhysicsConfig physics;  // collision weight and eps, friction
  double fps = 30;        // frames per second of the sequence (dt = 1 / fps)

  template <class V>
  void visit(V& v) {
    v("effects", effects);
    v("material", material);
    v("physics", physics);
    v("fps", fps, positive());
  }
};

struct ScoreInput {
  TriMesh garment_rest;                 // rest shape and faces, same vertex order as the frames
  std::vector<Eigen::MatrixXd> frames;  // T >= 2 frames of n x 3 positions, m (frame 0: start)
  Eigen::MatrixXd previous;             // n x 3, the frame before frame 0; empty: frame 0 (at rest)
  std::vector<Eigen::MatrixXd> body;    // empty, or T frames of nb x 3
  Eigen::MatrixXi body_faces;
  Effects effects;
  Material material;
  PhysicsConfig physics;
  double dt = 1.0 / 30.0;
};

struct ScoreResult {
  int frames = 0;                              // T, frame 0 included
  std::vector<EnergyReport> reports;           // frames 1..: each x_t against x_{t-1}, x_{t-2}
  std::vector<PenetrationFigures> penetration;  // one per report with a body, else empty
  int nonfinite_at_frame = -1;                 // the first frame whose energy is not finite, or -1
  EnergyReport mean;                           // term-wise mean over the scored frames
  double positive_mean = 0, positive_max = 0;  // J: stretch + bending + collision
  PenetrationSummary penetration_summary;
};

// Scores frames 1..T-1 (frame 0 is the start: no step produced it). Throws pb4u::Error on
// inconsistent input: vertex counts that differ from the rest mesh, body frames that are
// not one per garment frame, collision or friction without a body, fewer than 2 frames.
ScoreResult score_sequence(const ScoreInput& input);

// Outputs. `csv`: the columns of simulate's energies.csv (frame, the terms, total, and with
// a body penetrating_fraction and max_penetration_mm), frame 0's values "nan". `json`:
// {"frames", "scored_frames", "mean": {term: J, "total"}, "positive_mean", "positive_max",
// "penetrating_fraction", "max_penetrating_fraction", "max_penetration_mm",
// "nonfinite_at_frame", "per_frame": [{"frame": 1, term: J, ...}]}. `table`: the summary.
std::string score_csv(const ScoreResult& result);
std::string score_json(const ScoreResult& result);
std::string score_table(const ScoreResult& result, const std::string& title);

}  // namespace pb4u

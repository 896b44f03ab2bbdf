#pragma once
// `pb4u evaluate` (Table 1): every model (and optionally the reference solver) rolls out the
// held-out motions of a dataset (split `split`) from their LBS-initialised first frame, at
// each resolution level, with the config's effects and the evaluation material; each active
// term is averaged over the measured frames and then over sequences. With a body, the
// garment's penetration is measured too (physics/penetration.h). Without one (e.g. effects
// [gravity, pins]) each garment hangs from rest, pinned by rule, for max_frames frames.
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "pb4u/config/config_io.h"
#include "pb4u/rollout/divergence_guard.h"
#include "pb4u/rollout/refined_step.h"
#include "pb4u/model/model_file.h"
#include "pb4u/physics/energy_report.h"
#include "pb4u/scene/material.h"
#include "pb4u/physics/penetration.h"
#include "pb4u/physics/physics_config.h"
#include "pb4u/scene/waistband.h"

namespace pb4u {

// Pins of a body-less evaluation, by rule (scene/pins.h), for every garment alike.
struct EvalPins {
  double top_band = 0;  // m: pin the vertices within this distance of the garment's highest one

  template <class V>
  void visit(V& v) {
    v("top_band", top_band, non_negative());
  }
};

struct EvalConfig {
  std::string dataset = "data/generated/quick/quick.h5";  // written by `pb4u generate`
  std::vector<int> levels{1, 2, 3, 4};  // 1-based, as in the dataset
  std::vector<std::string> garments;    // garment names; empty = all
  std::string split = "test";  // the motions evaluated: the dataset's motions of this split
  std::vector<std::string> motions;     // motion names of that split; empty = all of them
  int max_sequences = 0;   // motions per garment and body, 0 = all
  int max_frames = 0;      // frames rolled out per sequence, 0 = the whole motion (needed > 0 without a body)
  int start_frame = 1;     // LBS-initialised start (needs the frame before it)
  double push_out_gap = 0.004;  // m, as in training: LBS frames pushed out of the body
  // How each rollout's frame 0 is reached, as a scene's body.start: "skinned" (the garment
  // skinned to the start frame's pose and pushed push_out_gap out of the body, the training
  // data's start) or "settled" (the reference solver carries the rest shape from the bind pose
  // to that pose in settle_steps steps, never inside the body: rollout/settled_start.h). Every
  // method of a sequence starts from the same frame; the settling is timed apart from them.
  std::string start = "skinned";
  int settle_steps = 10;
  std::vector<std::string> effects{"gravity", "collision", "friction"};
  EvalPins pins;           // with effect `pins`
  // With a body, these garments' waistbands ride on it (scene/waistband.h): a skirt's rollout
  // gains the effect `pins`. `waistband: {garments: []}` lets skirts slide off.
  WaistbandConfig waistband;
  Material material;       // the evaluation material (SPEC 2 defaults)
  PhysicsConfig physics;   // evaluation uses the final collision weight
  DivergenceConfig divergence;  // when a rollout stops as diverged
  RefineConfig refine;          // the networks' steps refined by the reference solver (physics.solver)
  // Each --checkpoint under these inference passes (model/pass_variants.h: shipped | none |
  // projection_strain | refined), its variants side by side; [none, shipped]: each network
  // alone beside the file's own passes.
  std::vector<std::string> passes{"shipped"};
  // When set, a PNG contact sheet (sim/preview.h) of the first network method's worst
  // sequence: the one with the largest mean positive energy over every level.
  std::string preview;
  // When set, every rollout's frames as CSV (eval/frames_csv.h):
  // <frames_dir>/lv<level>/<method>/<garment>_<motion>_<body>.csv.
  std::string frames_dir;
  // > 0: every minimum_every-th frame of every rollout, its step solved on to the energy's
  // minimum (to 0.001 mm, from the step where it stands): the distance (mm) and energy gap (J)
  // the residual estimates, measured (RolloutInput::minimum_every). A reference solve a sampled frame.
  int minimum_every = 0;

  template <class V>
  void visit(V& v) {
    v("dataset", dataset);
    v("levels", levels);
    v("garments", garments);
    v("split", split);
    v("motions", motions);
    v("max_sequences", max_sequences, int_at_least(0));
    v("max_frames", max_frames, int_at_least(0));
    v("start_frame", start_frame, int_at_least(1));
    v("push_out_gap", push_out_gap, in_range(0, 0.05));
    v("start", start, one_of({"skinned", "settled"}));
    v("settle_steps", settle_steps, int_in_range(1, 1000));
    v("effects", effects);
    v("pins", pins);
    v("waistband", waistband);
    v("material", material);
    v("physics", physics);
    v("divergence", divergence);
    v("refine", refine);
    v("passes", passes);
    v("preview", preview);
    v("frames_dir", frames_dir);
    v("minimum_every", minimum_every, int_at_least(0));
  }
};

// One rollout of one method: what the stability report compares across methods.
struct SequenceResult {
  std::string body, garment, motion;  // motion "rest": a body-less rollout from rest
  int frames = 0;                     // frames measured
  std::optional<EnergyReport> mean;   // over those frames; absent when none
  double positive_energy = 0;         // J: mean per frame of stretch + bending + collision
  double max_positive_energy = 0;     // J: its largest frame
  // mm: the median over its frames of the step's residual (EnergyReport::residual_mm), NaN where
  // not measured. A solve can end far from its minimum on a rare frame (a 1e7 mm residual), and
  // such a frame sets the mean alone; the median reads the typical frame.
  double median_residual_mm = NAN;
  MinimumSummary minimum;  // the frames sampled with minimum_every (none: frames 0)
  std::optional<PenetrationSummary> penetration;  // with a body (and a measured frame)
  bool diverged = false;
  int diverged_at_frame = -1;
  std::string diverged_reason;
};

// One method at one level.
struct MethodResult {
  std::string name;
  int64_t K = 0;                // propagation steps used (0: MGN / reference)
  std::optional<EnergyReport> mean;  // absent when no frame was finite
  std::optional<PenetrationSummary> penetration;  // with a body: frames, then sequences
  int sequences = 0, frames = 0;     // measured frames averaged
  bool diverged = false;
  int diverged_at_frame = -1;        // earliest, over sequences
  std::string diverged_sequence;     // "<garment>/<motion>" of that earliest divergence
  std::string diverged_reason;       // and why it stopped
  std::vector<SequenceResult> per_sequence;  // every rollout, in evaluation order
  double seconds = 0;                // wall time of the rollouts, measuring included
  // Median over the frames of one step's wall time (ms): the body contact query and the step
  // (a network's with its passes and refinement, or the solver's), as bench's latency; NaN
  // without a frame.
  double step_ms = 0;
  // mm: the median over every frame of every sequence of the step's residual (NaN where none was
  // measured); beside the mean, which a rare frame far from the minimum can set alone.
  double median_residual_mm = NAN;
  MinimumSummary minimum;  // over the sampled frames of every sequence (minimum_every)
};

struct LevelResult {
  int level = 0;
  int64_t triangles = 0, vertices = 0;  // mean over the garments evaluated
  int64_t K = 0;                        // of the first Pb4U-kind model (0 if none)
  std::vector<std::string> terms;       // active terms, Table-1 order
  std::vector<MethodResult> methods;
};

struct EvalMethod {
  std::string name;
  const ModelFile* model = nullptr;  // null: the reference solver
  // The solver's body contact when model is null ("penalty" | "barrier"); empty: the config's
  // physics.solver.contact.
  std::string solver_contact;
};

// Method names for `models`: from each config, duplicates suffixed with the file stem;
// `names` (may be shorter) overrides the first ones.
std::vector<std::string> method_names(const std::vector<ModelFile>& models,
                                      const std::vector<std::string>& names);

// Runs the evaluation (progress bar per level). Throws pb4u::Error on bad config / data.
std::vector<LevelResult> evaluate(const EvalConfig& config, const std::vector<EvalMethod>& methods);

// The paper's layout: per level, rows Stretch ... Friction, Total (and with a body the
// penetration rows Inside %, Inside max %, Depth max mm); one column per method; energies as
// 5.30E-02; the lowest value per row marked with '*'; diverged methods noted.
std::string format_table(const std::vector<LevelResult>& levels);
// level,triangles,vertices,method,K,term,value,diverged,diverged_at_frame; with a body the
// terms include penetrating_fraction, max_penetrating_fraction and max_penetration_mm.
std::string format_csv(const std::vector<LevelResult>& levels);
// SPEC 7 JSON, plus per method K, frames, the penetration keys (with a body), the divergence
// reason (when diverged) and "sequences": one object per rollout (SequenceResult).
std::string format_json(const std::vector<LevelResult>& levels);

}  // namespace pb4u

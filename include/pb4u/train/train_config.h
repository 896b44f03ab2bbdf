#pragma once
// `pb4u train` config (configs/train/*.yaml): what to train on, the model, the physics, and
// the optimisation schedule. Every constant of a run is here, so the effective config saved
// in the run directory reproduces it.
#include <string>
#include <vector>

#include "pb4u/config/config_io.h"
#include "pb4u/model/model_config.h"
#include "pb4u/scene/material.h"
#include "pb4u/physics/physics_config.h"
#include "pb4u/scene/waistband.h"
#include "pb4u/train/sampling.h"

namespace pb4u {

struct RunConfig {
  std::string out = "runs/quick";  // run directory: checkpoints/, metrics.jsonl, config.yaml
  int seed = 0;
  int steps = 2000;
  int batch = 1;                   // samples per step on each rank (gradients averaged over all)
  int checkpoint_every = 100;
  int keep_checkpoints = 3;
  std::string device = "cpu";      // cpu | cuda
  int threads = 0;                 // torch intra-op threads, 0 = all cores (--threads wins)
  // A training checkpoint or a `pb4u export` file whose weights and normaliser statistics start
  // a new run (fine-tuning; train/init_weights.h): step, optimiser and schedule start afresh
  // from this config. Ignored by --resume.
  std::string init_from;

  template <class V>
  void visit(V& v) {
    v("out", out);
    v("seed", seed, int_at_least(0));
    v("steps", steps, int_at_least(1));
    v("batch", batch, int_at_least(1));
    v("checkpoint_every", checkpoint_every, int_at_least(1));
    v("keep_checkpoints", keep_checkpoints, int_at_least(1));
    v("device", device, one_of({"cpu", "cuda"}));
    v("threads", threads, int_at_least(0));
    v("init_from", init_from);
  }
};

// data.scales: at least one factor, each in (0, 10].
Check<std::vector<double>> scale_factors();

struct TrainDataConfig {
  std::string dataset = "data/generated/quick/quick.h5";  // written by `pb4u generate`
  std::vector<int> levels{1};          // training levels (1-based, as in the dataset)
  std::vector<std::string> garments;   // template names to train on; empty = all
  double push_out_gap = 0.004;         // m: LBS frames push penetrating vertices this far out
  // Each training motion is also trained on played this many times faster (resampled, so a
  // 1/30 s step covers more of it): the body moves faster than any recorded motion, as
  // held-out motions may. Empty = the motions as recorded only.
  std::vector<double> speedups;
  // Each training sample's whole scene (garment, body, motion, pins) is scaled by one of these
  // factors, picked uniformly: a cloth c times smaller has edges c times shorter, so training
  // on the coarsest meshes also shows the network the short edges of finer ones (K's range
  // scales by 1 / c with them). Gravity, dt and the material stay. [1] = as generated.
  std::vector<double> scales{1.0};

  template <class V>
  void visit(V& v) {
    v("dataset", dataset);
    v("levels", levels);
    v("garments", garments);
    v("push_out_gap", push_out_gap, in_range(0, 0.05));
    v("speedups", speedups);
    v("scales", scales, scale_factors());
  }
};

struct OptimConfig {
  double lr = 1e-4;          // Adam learning rate at step 0
  double lr_final = 1e-5;    // reached at the last step (exponential decay)
  double grad_clip = 1.0;    // max global gradient norm
  template <class V>
  void visit(V& v) {
    v("lr", lr, positive());
    v("lr_final", lr_final, positive());
    v("grad_clip", grad_clip, positive());
  }
};

// Rollout length r grows from 1 to rollout_max, by one every steps_per_increase steps; the
// state is detached between rollout steps.
struct CurriculumConfig {
  int rollout_max = 5;
  int steps_per_increase = 400;
  template <class V>
  void visit(V& v) {
    v("rollout_max", rollout_max, int_at_least(1));
    v("steps_per_increase", steps_per_increase, int_at_least(1));
  }
};

// Training on the model's own states (HOOD-style autoregressive training, without
// backpropagating through time): each sample slot keeps `chains` trajectories that the model
// itself carries on along their motions. A sample continues one of them (picked at random)
// unless, with probability p_fresh, or when it has reached the motion's end or left the
// plausible (positive energy above restart_energy J), a fresh LBS-initialised one replaces it.
// The states the model reaches after tens to hundreds of its own steps, drift and
// penetrations included, are thus in the training mix. chains = 0: LBS starts only.
struct ReplayConfig {
  int chains = 0;
  double p_fresh = 0.2;
  double restart_energy = 20.0;  // J: stretch + bending + collision of the last step
  // The states a rollout carries on (to its next step and back into its chain) made sound as
  // inference makes them: edges limited to (1 + strain_limit) x rest, vertices pushed out of
  // the body to contact_projection m (physics/step_constraints.h); 0 = off. The loss is still
  // the raw prediction's: the network is trained from sound states, not through the passes.
  double strain_limit = 0;
  double contact_projection = 0;
  // > 0: the state carried on is then refined by this many reference-solver iterations
  // (rollout/refined_step.h; the solver's contact `refine_contact`: penalty or barrier, the
  // intersection-free one), with the sample's material and the final collision weight: the
  // chains follow what a sound rollout reaches. Float64 on the CPU; the loss is unchanged.
  int refine_iterations = 0;
  std::string refine_contact = "penalty";

  template <class V>
  void visit(V& v) {
    v("chains", chains, int_at_least(0));
    v("p_fresh", p_fresh, in_range(0, 1));
    v("restart_energy", restart_energy, positive());
    v("strain_limit", strain_limit, in_range(0, 10));
    v("contact_projection", contact_projection, in_range(0, 1));
    v("refine_iterations", refine_iterations, int_at_least(0));
    v("refine_contact", refine_contact, one_of({"penalty", "barrier"}));
  }
  bool constrains() const { return strain_limit > 0 || contact_projection > 0; }
};

struct TrainConfig {
  RunConfig run;
  TrainDataConfig data;
  ModelConfig model;
  PhysicsConfig physics;
  MaterialRanges materials;       // sampled per training sample (SPEC 2)
  EffectSampling effects;
  // With a body, these garments always train with their waistband riding on it (scene/waistband.h),
  // as evaluation and scenes hold them. Off by default (the shipped models trained without it).
  WaistbandConfig waistband{{}, 0.02};
  OptimConfig optim;
  CurriculumConfig curriculum;
  ReplayConfig replay;

  template <class V>
  void visit(V& v) {
    v("run", run);
    v("data", data);
    v("model", model);
    v("physics", physics);
    v("materials", materials);
    v("effects", effects);
    v("waistband", waistband);
    v("optim", optim);
    v("curriculum", curriculum);
    v("replay", replay);
  }
};

// Learning rate at `step` of `steps`: exponential from lr to lr_final.
double learning_rate(const OptimConfig& optim, int64_t step, int64_t steps);
// Rollout length at `step`.
int rollout_length(const CurriculumConfig& curriculum, int64_t step);

}  // namespace pb4u

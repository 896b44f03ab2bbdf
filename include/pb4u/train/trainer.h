#pragma once
// Self-supervised training (SPEC 4, issue 6): sample a frame of a training motion, a garment
// at a training level, a material and an effect set; start from the LBS-initialised state;
// roll the model out r steps (state detached between steps); minimise the sum of the active
// physics terms.
//
// A step trains on run.batch samples per rank; with a DistributedGroup of N ranks the step's
// batch is the N * run.batch samples of all ranks, gradients averaged over it (issue 10).
// Sample j of rank R is global sample g = R * run.batch + j, drawn from an RNG seeded by
// (run.seed, step, g) alone, so the samples of a step do not depend on how they are split
// over ranks, and a resumed run needs no saved RNG state. Every sample sees the normaliser
// statistics of the start of the step plus its own; the step adds all samples' statistics.
// Hence N ranks of batch b train exactly like one process of batch N * b.
#include <torch/torch.h>

#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "pb4u/body/body.h"
#include "pb4u/body/skeleton.h"
#include "pb4u/garment/garment.h"
#include "pb4u/graph/garment_topology.h"
#include "pb4u/model/pb4u_net.h"
#include "pb4u/physics/cloth_geometry.h"
#include "pb4u/train/distributed.h"
#include "pb4u/train/step_profile.h"
#include "pb4u/train/train_config.h"

namespace pb4u {

// What training samples from: bodies, garments at the training levels, training motions.
struct TrainingData {
  std::vector<Body> bodies;
  std::vector<Garment> garments;
  std::vector<int> garment_body;  // body index of each garment
  std::vector<Motion> motions;
  std::vector<int> motion_body;   // body index of each motion (same skeleton)
};

// One step's outcome, also a metrics.jsonl row. Loss and terms are means over the step's
// samples on all ranks (a term over the samples that have it); rollout and K are those of
// this rank's first sample.
struct StepResult {
  int64_t step = 0;
  double loss = 0;                  // J: mean over rollout steps of the total energy
  std::vector<std::pair<std::string, double>> terms;  // J, mean over rollout steps
  double lr = 0, seconds = 0, collision_weight = 0;
  int rollout = 1;
  int64_t K = 0;
  int64_t samples = 1;              // the step's batch over all ranks
  bool skipped = false;             // non-finite loss or gradient on any rank: no update
  int age = 0;                      // model steps this rank's first sample had behind it (replay)
};

// A training sample's garment on its motion (replay): which garment, motion and frame, what
// the cloth is made of, the effects and pins, and the garment's state there (training device,
// float32). A fresh one starts from the LBS-initialised frame; `age` counts the model's own
// steps since.
struct Trajectory {
  int garment = -1, motion = -1, frame = 0;
  Material material;
  Effects effects;
  torch::Tensor x, x_prev;    // (n, 3) m at `frame` and the frame before
  torch::Tensor pinned;       // (n) bool, defined when effects.pins
  torch::Tensor pin_anchor;   // (n, 3) m: where pins hold without a body
  int age = 0;
  int scale = 0;              // index into data.scales: the whole scene is that many times its size

  bool active() const { return garment >= 0; }
};

class Trainer {
 public:
  // config_yaml: the effective config, stored in every checkpoint. resume: continue from the
  // newest checkpoint in <run.out>/checkpoints (an error if there is none). group: the ranks
  // of a data-parallel run (null = this process alone). Only rank 0 reads and writes the run
  // directory; it sends the other ranks its checkpoint and weights, so they need the
  // dataset but not the run directory. Every rank must pass the same config.
  Trainer(TrainConfig config, std::string config_yaml, TrainingData data, bool resume,
          std::shared_ptr<DistributedGroup> group = nullptr);

  // Trains until run.steps (or until `stop_at` steps, if smaller and >= 0, as if the run
  // were interrupted there) with a progress bar; checkpoints and metrics as configured.
  void run(int64_t stop_at = -1);
  // One optimisation step (exposed for tests).
  StepResult train_step();
  // Times every following step's stages into `profile` (null: stop). On a GPU each stage
  // ends with a device synchronisation, which the unprofiled steps do not pay.
  void set_profile(StepProfile* profile) { profile_ = profile; }

  int64_t step() const { return step_; }
  // The replay chains of each batch slot (inactive ones included), for tests.
  const std::vector<std::vector<Trajectory>>& replay_chains() const { return chains_; }
  Pb4uNet& model() { return model_; }
  const std::string& run_dir() const { return config_.run.out; }

 private:
  struct SampleResult {
    double loss = 0;  // mean over rollout steps of the total energy
    std::vector<std::pair<std::string, double>> terms;
    int rollout = 1;
    int64_t K = 0;
    int age = 0;
  };
  // One sample's rollout; its gradients accumulate into the parameters' .grad. `slot`: the
  // sample's index in this rank's batch, whose replay chains it continues.
  SampleResult train_sample(std::mt19937_64& rng, int slot, int rollout, double collision_weight);
  // A fresh LBS-initialised trajectory with room for `rollout` steps.
  Trajectory fresh_trajectory(std::mt19937_64& rng, int rollout);
  void save(bool final_checkpoint);
  void start_group(bool resume);
  bool is_root() const { return !group_ || group_->is_root(); }

  TrainConfig config_;
  std::string config_yaml_;
  TrainingData data_;
  torch::Device device_;
  Pb4uNet model_{nullptr};
  std::unique_ptr<torch::optim::Adam> optimizer_;
  // Per garment and data.scales factor, at variant(garment, scale).
  std::vector<GarmentTopology> topology_;
  std::vector<ClothGeometry> cloth_;
  std::vector<ClothGeometry> refine_cloth_;  // float64 on the CPU, with replay.refine_iterations
  int variant(int garment, int scale) const { return garment * int(config_.data.scales.size()) + scale; }
  std::shared_ptr<DistributedGroup> group_;
  std::vector<std::string> term_names_;  // all terms, in Table-1 order: slots of the reduction
  // Replay chains per batch slot (config_.replay.chains each); they restart empty on resume.
  std::vector<std::vector<Trajectory>> chains_;
  StepProfile* profile_ = nullptr;
  // Charges the time since the last lap to `stage` when profiling.
  void lap(const char* stage);
  int64_t step_ = 0;
  int64_t skipped_steps_ = 0;
  double elapsed_seconds_ = 0;
};

}  // namespace pb4u

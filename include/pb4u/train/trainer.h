#pragma once
// Self-supervised training (SPEC 4, issue 6): sample a frame of a training motion, a garment
// at a training level, a material and an effect set; start from the LBS-initialised state;
// roll the model out r steps (state detached between steps); minimise the sum of the active
// physics terms.
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

// One step's outcome, also a metrics.jsonl row.
struct StepResult {
  int64_t step = 0;
  double loss = 0;                  // J: mean over rollout steps of the total energy
  std::vector<std::pair<std::string, double>> terms;  // J, mean over rollout steps
  double lr = 0, seconds = 0, collision_weight = 0;
  int rollout = 1;
  int64_t K = 0;
  bool skipped = false;             // non-finite loss or gradient: no update
};

class Trainer {
 public:
  // config_yaml: the effective config, stored in every checkpoint. resume: continue from the
  // newest checkpoint in <run.out>/checkpoints (an error if there is none).
  Trainer(TrainConfig config, std::string config_yaml, TrainingData data, bool resume);

  // Trains until run.steps (or until `stop_at` steps, if smaller and >= 0, as if the run
  // were interrupted there) with a progress bar; checkpoints and metrics as configured.
  void run(int64_t stop_at = -1);
  // One optimisation step (exposed for tests).
  StepResult train_step();

  int64_t step() const { return step_; }
  Pb4uNet& model() { return model_; }
  const std::string& run_dir() const { return config_.run.out; }

 private:
  void save(bool final_checkpoint);
  std::string host_rng_state() const;

  TrainConfig config_;
  std::string config_yaml_;
  TrainingData data_;
  torch::Device device_;
  Pb4uNet model_{nullptr};
  std::unique_ptr<torch::optim::Adam> optimizer_;
  std::vector<GarmentTopology> topology_;
  std::vector<ClothGeometry> cloth_;
  std::mt19937_64 rng_;
  int64_t step_ = 0;
  int64_t skipped_steps_ = 0;
  double elapsed_seconds_ = 0;
};

}  // namespace pb4u

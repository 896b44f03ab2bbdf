// Training on the tiny dataset: the loss falls, a stopped-and-resumed run matches an
// uninterrupted one, the CLI writes its run files, and SIGKILL never leaves a bad checkpoint.
#include <gtest/gtest.h>

#include <iostream>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <random>
#include <set>
#include <thread>

#include "pb4u/graph/garment_topology.h"
#include "pb4u/model/model_file.h"
#include "pb4u/model/checkpoint.h"
#include "pb4u/train/metrics_log.h"
#include "pb4u/train/step_profile.h"
#include "pb4u/train/trainer.h"
#include "pb4u/train/training_data.h"
#include "pb4u/util/error.h"
#include "pb4u/util/runtime.h"
#include "test_util.h"

namespace pb4u {
namespace {
namespace fs = std::filesystem;

using test::kSource;

TrainConfig tiny_config(const std::string& out, std::vector<std::string> sets = {}) {
  sets.push_back("data.dataset=" + test::tiny_dataset());
  sets.push_back("run.out=" + out);
  return load_config<TrainConfig>(kSource + "/configs/train/tiny.yaml", sets);
}

Trainer make_trainer(const TrainConfig& c, bool resume = false) {
  return Trainer(c, config_to_yaml(c), load_training_data(c.data), resume);
}

// The samples of a step depend on (seed, step) only, so a trained run and a frozen one (lr ~ 0)
// see the same frames: a paired comparison. A plain "late loss < early loss" over a few steps
// is decided by which samples come when: the tiny skirt's LBS frames tear (10-200 J of stretch
// against ~0.2 J), and the energy of a frame is mostly that of its input state.
TEST(Trainer, TrainingLowersTheEnergyOfTheSameSamples) {
  configure_threads(1);
  auto non_gravity = [](const StepResult& s) {
    // Gravity's energy is measured from y = 0 (SPEC 3.4): its value swings with the garment
    // height while its gradient is a constant. Judge the other terms.
    double e = 0;
    for (const auto& [name, value] : s.terms)
      if (name != "gravity") e += value;
    return e;
  };
  auto energies = [&](const std::string& tag, std::vector<std::string> sets) {
    sets.push_back("physics.collision.ramp=constant");
    TrainConfig c = tiny_config(test::temp_dir(tag), sets);
    Trainer trainer = make_trainer(c);
    std::vector<double> out;
    for (int i = 0; i < c.run.steps; ++i) {
      StepResult s = trainer.train_step();
      EXPECT_TRUE(std::isfinite(s.loss)) << tag << " step " << s.step;
      EXPECT_FALSE(s.terms.empty());
      out.push_back(non_gravity(s));
    }
    return out;
  };
  const auto trained = energies("train_loss", {});
  const auto frozen = energies("train_frozen", {"optim.lr=1e-12", "optim.lr_final=1e-12"});
  ASSERT_EQ(trained.size(), frozen.size());
  EXPECT_DOUBLE_EQ(trained[0], frozen[0]);  // same first sample, same initial weights
  const size_t from = 10;                   // give the optimiser a few steps
  int lower = 0;
  double sum_trained = 0, sum_frozen = 0;
  for (size_t i = from; i < trained.size(); ++i) {
    lower += trained[i] < frozen[i];
    sum_trained += trained[i];
    sum_frozen += frozen[i];
  }
  // On the tiny config training lowers the energy by ~1% in 40 steps (seeds 0-3), on most
  // samples.
  EXPECT_GE(lower, 0.5 * (trained.size() - from)) << "trained lower on " << lower << " of " << trained.size() - from;
  EXPECT_LT(sum_trained, sum_frozen);
}

// Replay: with one chain and no fresh starts, each step continues the state the model itself
// reached the step before (age 0, 1, 2, ...) until the motion ends (12 frames in tiny); pinned
// samples (p_pins = 1) train like the others.
TEST(Trainer, ReplayChainsCarryTheModelsOwnStatesOn) {
  configure_threads(1);
  TrainConfig c = tiny_config(test::temp_dir("train_replay"),
                              {"replay.chains=1", "replay.p_fresh=0", "replay.restart_energy=1e12",
                               "curriculum.rollout_max=1", "effects.p_pins=1"});
  Trainer trainer = make_trainer(c);
  int previous = -1, continued = 0, restarts = 0;
  for (int i = 0; i < 14; ++i) {
    StepResult s = trainer.train_step();
    ASSERT_TRUE(std::isfinite(s.loss)) << "step " << s.step;
    if (i == 0) EXPECT_EQ(s.age, 0);
    if (s.age > 0) {
      EXPECT_EQ(s.age, previous + 1) << "step " << s.step;
      ++continued;
    } else {
      ++restarts;
    }
    previous = s.age;
  }
  EXPECT_GE(continued, 5);
  EXPECT_GE(restarts, 2) << "a chain restarts at its motion's end";
  // Without replay every sample starts fresh.
  TrainConfig plain = tiny_config(test::temp_dir("train_no_replay"));
  Trainer fresh = make_trainer(plain);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(fresh.train_step().age, 0);
}

TEST(Trainer, StoppedAndResumedRunEqualsUninterrupted) {
  configure_threads(1);
  const std::string a_dir = test::temp_dir("train_a"), b_dir = test::temp_dir("train_b");
  TrainConfig a_cfg = tiny_config(a_dir, {"run.steps=20"});
  Trainer a = make_trainer(a_cfg);
  a.run();
  TrainConfig b_cfg = tiny_config(b_dir, {"run.steps=20"});
  {
    Trainer b = make_trainer(b_cfg);
    b.run(/*stop_at=*/10);
    EXPECT_EQ(b.step(), 10);
  }
  Trainer b = make_trainer(b_cfg, /*resume=*/true);
  EXPECT_EQ(b.step(), 10);
  b.run();
  EXPECT_EQ(b.step(), 20);
  auto pa = a.model()->named_parameters(), pb = b.model()->named_parameters();
  for (const auto& p : pa) EXPECT_TRUE(torch::equal(p.value(), pb[p.key()])) << p.key();
  auto ba = a.model()->named_buffers(), bb = b.model()->named_buffers();
  for (const auto& p : ba) EXPECT_TRUE(torch::equal(p.value(), bb[p.key()])) << p.key();
  // The resumed run's metrics have each step once.
  auto rows = read_metrics(b_dir + "/metrics.jsonl");
  ASSERT_EQ(rows.size(), 20u);
  for (size_t i = 0; i < rows.size(); ++i) EXPECT_EQ(rows[i][0].second, double(i + 1));
}

// --profile: every step's stages are timed, they add up to the step, and profiling changes
// nothing the run computes.
TEST(Trainer, ProfiledStepsTimeTheirStagesAndTrainTheSame) {
  configure_threads(1);
  const std::string a_dir = test::temp_dir("profile_a"), b_dir = test::temp_dir("profile_b");
  Trainer a = make_trainer(tiny_config(a_dir, {"run.steps=6"}));
  a.run();
  Trainer b = make_trainer(tiny_config(b_dir, {"run.steps=6"}));
  StepProfile profile;
  b.set_profile(&profile);
  b.run();
  auto pa = a.model()->named_parameters(), pb = b.model()->named_parameters();
  for (const auto& p : pa) EXPECT_TRUE(torch::equal(p.value(), pb[p.key()])) << p.key();

  EXPECT_EQ(profile.steps(), 6);
  std::set<std::string> stages;
  double mean_sum = 0;
  for (const auto& r : profile.rows()) {
    stages.insert(r.stage);
    EXPECT_GE(r.mean_ms, 0) << r.stage;
    mean_sum += r.mean_ms;
  }
  for (const char* stage : {"graph build", "forward: encode", "forward: propagation + update", "forward: blocks",
                            "term: stretch", "term: inertia", "backward", "clip + Adam"})
    EXPECT_TRUE(stages.count(stage)) << stage;
  // The stages cover the step: their mean sum is the mean of the steps' recorded wall time.
  const auto rows = read_metrics(b_dir + "/metrics.jsonl");
  double step_ms = 0;
  for (const auto& row : rows)
    for (const auto& [key, value] : row)
      if (key == "step_seconds") step_ms += 1000 * value / double(rows.size());
  EXPECT_NEAR(mean_sum, step_ms, 0.05 * step_ms + 0.5);
  EXPECT_NE(profile.table().find("| backward |"), std::string::npos);
}

// replay.strain_limit / replay.contact_projection: the states the chains carry on are
// constrained as inference constrains a step; without them the tiny model's chains stretch.
// The largest edge strain over the active replay chains' states (some must be active).
double largest_strain(Trainer& t, const TrainingData& data) {
  double worst = 0;
  int active = 0;
  for (const auto& slot : t.replay_chains())
    for (const Trajectory& tr : slot) {
      if (!tr.active()) continue;
      ++active;
      const GarmentTopology topo = build_garment_topology(data.garments[tr.garment].mesh);
      auto d = (tr.x.index_select(0, topo.receivers) - tr.x.index_select(0, topo.senders)).norm(2, 1);
      worst = std::max(worst, (d / topo.rest_length - 1).max().item<double>());
    }
  EXPECT_GT(active, 0);
  return worst;
}

TEST(Trainer, ReplayCarriesConstrainedStates) {
  configure_threads(1);
  const std::vector<std::string> sets = {"run.steps=30", "replay.chains=2", "replay.p_fresh=0.05"};
  TrainConfig plain_cfg = tiny_config(test::temp_dir("replay_plain"), sets);
  Trainer plain = make_trainer(plain_cfg);
  plain.run();
  const TrainingData data = load_training_data(plain_cfg.data);
  EXPECT_GT(largest_strain(plain, data), 0.2);  // else this test shows nothing

  auto constrained_sets = sets;
  constrained_sets.insert(constrained_sets.end(), {"replay.strain_limit=0.1", "replay.contact_projection=0.002"});
  Trainer constrained = make_trainer(tiny_config(test::temp_dir("replay_constrained"), constrained_sets));
  constrained.run();
  // Limit then project, up to 10 rounds, until within 1.1x the limit or the rounds run out
  // (step_constraints.h). Where the projection and the limit disagree the rounds can run out: on
  // the tiny t-shirt whose rest mesh is cleared of the mannequin (2026-11-28) a carried state
  // ended at 1.2x the limit. Unconstrained the chains pass 2x.
  EXPECT_LE(largest_strain(constrained, data), 0.125);
}

// replay.refine_iterations: the states the chains carry on are refined by the solver, whose
// stretch pulls the tiny model's stretched edges back in; the profile times it.
TEST(Trainer, ReplayCarriesRefinedStates) {
  configure_threads(1);
  const std::vector<std::string> sets = {"run.steps=30", "replay.chains=2", "replay.p_fresh=0.05"};
  TrainConfig plain_cfg = tiny_config(test::temp_dir("replay_plain_r"), sets);
  Trainer plain = make_trainer(plain_cfg);
  plain.run();
  const TrainingData data = load_training_data(plain_cfg.data);
  const double plain_strain = largest_strain(plain, data);
  EXPECT_GT(plain_strain, 0.2);  // else this test shows nothing

  auto refined_sets = sets;
  refined_sets.push_back("replay.refine_iterations=10");
  Trainer refined = make_trainer(tiny_config(test::temp_dir("replay_refined"), refined_sets));
  StepProfile profile;
  refined.set_profile(&profile);
  refined.run();
  const double refined_strain = largest_strain(refined, data);
  // 0.30 -> 0.15 on the tiny dataset with cleared rest meshes (2026-11-28): two different
  // training runs, so the ratio is a sample, not a bound the solver guarantees.
  EXPECT_LT(refined_strain, 0.6 * plain_strain) << plain_strain << " -> " << refined_strain;
  EXPECT_NE(profile.table().find("| replay: refine the state carried on |"), std::string::npos);
  for (const auto& slot : refined.replay_chains())
    for (const Trajectory& tr : slot)
      if (tr.active()) EXPECT_EQ(tr.x.scalar_type(), torch::kFloat32);  // back in the training dtype
}

TEST(StepProfile, MediansAndMeansPerStepWithAbsentStagesAsZero) {
  StepProfile p;
  for (int step = 0; step < 3; ++step) {
    p.begin_step();
    p.add("a", 1.0 + step);
    if (step == 1) p.add("b", 6.0);
  }
  auto rows = p.rows();
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].stage, "a");
  EXPECT_DOUBLE_EQ(rows[0].median_ms, 2.0);
  EXPECT_DOUBLE_EQ(rows[1].median_ms, 0.0);  // b ran on one step of three
  EXPECT_DOUBLE_EQ(rows[1].mean_ms, 2.0);
  EXPECT_DOUBLE_EQ(p.median_step_ms(), 3.0);  // steps of 1, 8 and 3 ms
}

// Fine-tuning: run.init_from starts a new run (step 0, fresh optimiser) from another run's
// weights and normaliser statistics; the model config may differ where shapes do not.
TEST(Trainer, InitFromStartsANewRunFromAnotherRunsWeights) {
  configure_threads(1);
  const std::string a_dir = test::temp_dir("init_a"), b_dir = test::temp_dir("init_b");
  Trainer a = make_trainer(tiny_config(a_dir, {"run.steps=12"}));
  a.run();
  TrainConfig b_cfg = tiny_config(b_dir, {"run.init_from=" + a_dir + "/final.pt", "run.seed=7",
                                          "model.update_scaling=detail"});
  Trainer b = make_trainer(b_cfg);
  EXPECT_EQ(b.step(), 0);
  auto pa = a.model()->named_parameters(), pb = b.model()->named_parameters();
  for (const auto& p : pa) EXPECT_TRUE(torch::equal(p.value(), pb[p.key()])) << p.key();
  auto ba = a.model()->named_buffers(), bb = b.model()->named_buffers();
  for (const auto& p : ba) EXPECT_TRUE(torch::equal(p.value(), bb[p.key()])) << p.key();
  b.run(/*stop_at=*/2);
  EXPECT_EQ(b.step(), 2);
  // Without init_from the same seed-7 run starts from other weights.
  Trainer c = make_trainer(tiny_config(test::temp_dir("init_c"), {"run.seed=7"}));
  bool differs = false;
  for (const auto& p : pa) differs = differs || !torch::equal(p.value(), c.model()->named_parameters()[p.key()]);
  EXPECT_TRUE(differs);
  // A missing file names the key and the file.
  try {
    make_trainer(tiny_config(test::temp_dir("init_d"), {"run.init_from=" + a_dir + "/missing.pt"}));
    ADD_FAILURE() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("run.init_from"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("missing.pt"), std::string::npos) << e.what();
  }
}

// run.init_from also takes a portable export (what survives a lost run directory): the new
// run starts from its weights and normaliser statistics; another shape names file and tensor.
TEST(Trainer, InitFromAnExportedModelFile) {
  configure_threads(1);
  const std::string a_dir = test::temp_dir("init_export_a");
  Trainer a = make_trainer(tiny_config(a_dir, {"run.steps=6"}));
  a.run();
  const std::string exported = a_dir + "/model.h5";
  export_model_file(load_model_file(a_dir + "/final.pt"), exported);
  Trainer b = make_trainer(tiny_config(test::temp_dir("init_export_b"), {"run.init_from=" + exported, "run.seed=7"}));
  EXPECT_EQ(b.step(), 0);
  auto pa = a.model()->named_parameters(), pb = b.model()->named_parameters();
  ASSERT_EQ(pa.size(), pb.size());
  for (const auto& p : pa) EXPECT_TRUE(torch::equal(p.value(), pb[p.key()])) << p.key();
  auto ba = a.model()->named_buffers(), bb = b.model()->named_buffers();
  ASSERT_EQ(ba.size(), bb.size());
  for (const auto& p : ba) EXPECT_TRUE(torch::equal(p.value(), bb[p.key()])) << p.key();
  b.run(/*stop_at=*/2);
  EXPECT_EQ(b.step(), 2);
  try {
    make_trainer(tiny_config(test::temp_dir("init_export_c"), {"run.init_from=" + exported, "model.latent=9"}));
    ADD_FAILURE() << "expected an error";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("run.init_from"), std::string::npos) << what;
    EXPECT_NE(what.find("model.h5"), std::string::npos) << what;
    EXPECT_NE(what.find("shape"), std::string::npos) << what;
  }
}

TEST(TrainCommand, WritesRunFilesAndRefusesToClobber) {
  const std::string out = test::temp_dir("train_cli") + "/run";
  const std::string args = "-q train --config " + kSource + "/configs/train/tiny.yaml --set run.steps=6 "
                           "--set run.checkpoint_every=3 --set data.dataset=" + test::tiny_dataset() +
                           " --out " + out;
  auto r = test::run_pb4u(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* f : {"/config.yaml", "/metrics.jsonl", "/final.pt", "/checkpoints/step_00000006.pt"})
    EXPECT_TRUE(fs::exists(out + f)) << f;
  auto rows = read_metrics(out + "/metrics.jsonl");
  ASSERT_EQ(rows.size(), 6u);
  std::set<std::string> keys;
  for (const auto& kv : rows[0]) keys.insert(kv.first);
  for (const char* k : {"step", "loss", "lr", "seconds", "stretch", "bending", "inertia"})
    EXPECT_TRUE(keys.count(k)) << k;
  r = test::run_pb4u(args);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--resume"), std::string::npos) << r.err;
  r = test::run_pb4u(args + " --resume");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = test::run_pb4u("-q train --config " + kSource + "/configs/train/tiny.yaml --set model.widht=3");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("model.widht"), std::string::npos) << r.err;
}

TEST(TrainCommand, SigkillAlwaysLeavesALoadableCheckpoint) {
  const std::string out = test::temp_dir("train_kill") + "/run";
  const std::string cmd = std::string(PB4U_BINARY) + " -q --threads 1 train --config " + kSource +
                          "/configs/train/tiny.yaml --set run.steps=400 --set run.checkpoint_every=1"
                          " --set data.dataset=" + test::tiny_dataset() + " --out " + out;
  std::mt19937 rng(11);
  int64_t last_step = 0;
  auto latest_step = [&]() -> int64_t {
    try {  // the file may be pruned between listing and reading it
      std::string latest = latest_checkpoint(out + "/checkpoints");
      return latest.empty() ? 0 : read_checkpoint_meta(latest).step;
    } catch (const Error&) {
      return 0;
    }
  };
  for (int round = 0; round < 4; ++round) {
    pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      std::string run = cmd + (round > 0 ? " --resume" : "") + " >/dev/null 2>&1";
      execl("/bin/sh", "sh", "-c", ("exec " + run).c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
    // Wait for a checkpoint newer than the last round's (the resumed run continues), then
    // kill at a random moment (mid-write included).
    auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (latest_step() <= last_step && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    std::this_thread::sleep_for(std::chrono::milliseconds(std::uniform_int_distribution<int>(0, 700)(rng)));
    kill(pid, SIGKILL);
    int status = 0;
    waitpid(pid, &status, 0);
    std::string latest = latest_checkpoint(out + "/checkpoints");
    ASSERT_FALSE(latest.empty()) << "round " << round;
    int64_t step = 0;
    EXPECT_NO_THROW(step = read_checkpoint_meta(latest).step) << latest;
    EXPECT_GT(step, last_step) << "round " << round << ": the resumed run made no progress";
    last_step = step;
  }
}

}  // namespace
}  // namespace pb4u

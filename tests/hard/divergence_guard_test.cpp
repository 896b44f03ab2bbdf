// The divergence guard (issue 9): a rollout that goes non-finite stops at that frame, names
// the worst vertex and keeps every frame before it on disk; training skips a non-finite step,
// counts it in metrics.jsonl and leaves the weights untouched.
#include <gtest/gtest.h>

#include <limits>
#include <map>

#include "hard_case.h"
#include "pb4u/sim/point_cache.h"
#include "pb4u/sim/rollout_writer.h"
#include "pb4u/train/metrics_log.h"
#include "pb4u/train/trainer.h"
#include "pb4u/train/training_data.h"
#include "pb4u/util/runtime.h"
#include "test_util.h"

namespace pb4u {
namespace {

TEST(DivergenceGuard, RolloutStopsAtTheFirstNonFiniteFrameAndNamesTheVertex) {
  TriMesh cloth = hard::lattice_cloth(6, 6, 0.03);
  RolloutInput in = hard::still_start(cloth, Effects::from_names({"gravity", "pins"}, "test"), Material{}, 8);
  const int bad_frame = 4, bad_vertex = 17;
  int frame = 0;
  StepFunction solver = reference_stepper({});
  StepFunction step = [&](const FrameState& s, const ClothGeometry& c, const TermList& t, const BodyContact* b) {
    torch::Tensor x = solver(s, c, t, b);
    if (++frame == bad_frame) x[bad_vertex][1] = std::numeric_limits<double>::infinity();
    return x;
  };
  const std::string dir = test::temp_dir("diverge_writer");
  RolloutOutputs outputs;
  outputs.mesh_format = "none";
  RolloutWriter writer(dir, cloth.F, Eigen::MatrixXi(), outputs);
  writer.add_frame(in.x0, Eigen::MatrixXd(), {{"total", 0.0}});
  std::vector<int> seen;
  RolloutResult r = run_rollout(in, step, PhysicsConfig{}, [&](int f, const Eigen::MatrixXd& x, const EnergyReport& e) {
    seen.push_back(f);
    writer.add_frame(x, Eigen::MatrixXd(), {{"total", e.total}});
  });
  writer.finish();
  EXPECT_TRUE(r.diverged);
  EXPECT_EQ(r.diverged_at_frame, bad_frame);
  EXPECT_EQ(r.worst_vertex, bad_vertex);
  EXPECT_EQ(r.reports.size(), size_t(bad_frame - 1));
  EXPECT_EQ(seen, (std::vector<int>{1, 2, 3}));
  // The start frame and the finite frames before the divergence, all finite, on disk.
  auto cache = read_pc2(dir + "/garment.pc2");
  ASSERT_EQ(cache.size(), size_t(bad_frame));
  for (const auto& frame_positions : cache) EXPECT_TRUE(frame_positions.allFinite());
}

TEST(DivergenceGuard, TrainingSkipsANonFiniteStepAndKeepsTheWeights) {
  configure_threads(1);
  const std::string out = test::temp_dir("train_nonfinite");
  TrainConfig c = load_config<TrainConfig>(std::string(PB4U_SOURCE_DIR) + "/configs/train/tiny.yaml",
                                           {"data.dataset=" + test::tiny_dataset(), "run.out=" + out,
                                            "run.steps=3", "run.checkpoint_every=1"});
  Trainer trainer(c, config_to_yaml(c), load_training_data(c.data), false);
  trainer.run(1);
  // A NaN in one decoder bias makes the loss and every gradient behind it non-finite.
  torch::Tensor bias;
  for (auto& p : trainer.model()->decoder->named_parameters())
    if (p.key().find("bias") != std::string::npos) bias = p.value();
  ASSERT_TRUE(bias.defined());
  std::map<std::string, torch::Tensor> before;
  for (auto& p : trainer.model()->named_parameters()) before[p.key()] = p.value().clone();
  const torch::Tensor saved = bias.detach().clone();
  {
    torch::NoGradGuard guard;
    bias.fill_(std::numeric_limits<float>::quiet_NaN());
  }
  trainer.run(2);
  {
    torch::NoGradGuard guard;
    bias.copy_(saved);
  }
  for (auto& p : trainer.model()->named_parameters())
    EXPECT_TRUE(torch::equal(p.value(), before[p.key()])) << p.key() << " changed by a skipped step";
  trainer.run();
  EXPECT_EQ(trainer.step(), 3);
  bool updated = false;
  for (auto& p : trainer.model()->named_parameters()) {
    EXPECT_TRUE(torch::isfinite(p.value()).all().item<bool>()) << p.key();
    updated = updated || !torch::equal(p.value(), before[p.key()]);
  }
  EXPECT_TRUE(updated) << "the step after the skipped one trains again";
  auto rows = read_metrics(out + "/metrics.jsonl");
  ASSERT_EQ(rows.size(), 3u);
  auto value = [&](int row, const std::string& key) {
    for (const auto& [k, v] : rows[row])
      if (k == key) return v;
    ADD_FAILURE() << "no " << key << " in row " << row;
    return -1.0;
  };
  EXPECT_EQ(value(0, "skipped_steps"), 0.0);
  EXPECT_EQ(value(1, "skipped_steps"), 1.0);
  EXPECT_EQ(value(2, "skipped_steps"), 1.0);
  EXPECT_TRUE(std::isfinite(value(2, "loss")));
}

}  // namespace
}  // namespace pb4u

// The divergence guard (issues 9, 14): a rollout that goes non-finite stops at that frame,
// names the worst vertex and keeps every frame before it on disk; one whose positive energy
// exceeds a multiple of its start stops at that frame, checked against StVK in closed form; a
// calm rollout runs to its end; training skips a non-finite step, counts it in metrics.jsonl
// and leaves the weights untouched.
#include <gtest/gtest.h>

#include <limits>
#include <map>
#include <memory>

#include "hard_case.h"
#include "pb4u/eval/evaluate.h"
#include "pb4u/mesh/geometry.h"
#include "pb4u/io/point_cache.h"
#include "pb4u/sim/rollout_writer.h"
#include "pb4u/sim/simulate.h"
#include "pb4u/util/error.h"
#include "pb4u/train/metrics_log.h"
#include "pb4u/train/trainer.h"
#include "pb4u/train/training_data.h"
#include "pb4u/util/runtime.h"
#include "test_util.h"

namespace pb4u {
namespace {

TEST(DivergenceGuard, RolloutStopsAtTheFirstNonFiniteFrameAndNamesTheVertex) {
  TriMesh cloth = test::lattice_cloth(6, 6, 0.03);
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
  RolloutResult r = run_rollout(in, step, PhysicsConfig{}, [&](int f, const Eigen::MatrixXd& x, const EnergyReport& e,
                                                                const PenetrationFigures*) {
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

// A stepper that scales the flat rest cloth in its plane by 1 + growth * k at its k-th step.
StepFunction stretching_stepper(const TriMesh& cloth, double growth) {
  auto calls = std::make_shared<int>(0);
  const Eigen::RowVector3d centre = cloth.V.colwise().mean();
  return [cloth, growth, calls, centre](const FrameState&, const ClothGeometry&, const TermList&, const BodyContact*) {
    const double s = 1 + growth * ++*calls;
    Eigen::MatrixXd x = (cloth.V.rowwise() - centre) * s;
    return matrix_to_tensor(x.rowwise() + centre);
  };
}

// StVK energy (J) of a flat cloth of area A scaled uniformly by s in its plane (SPEC 3.1):
// F = s I, G = (s^2 - 1) / 2 I, psi = mu tr(G^2) + lambda / 2 tr(G)^2 = 2 (mu + lambda) g^2.
double scaled_stretch_energy(double area, const Material& m, double s) {
  const double g = (s * s - 1) / 2;
  return area * m.thickness * 2 * (m.mu + m.lambda) * g * g;
}

// The first frame k >= 2 whose positive energy exceeds ratio x max(frame 1's, floor).
int expected_trip_frame(double area, const Material& m, double growth, const DivergenceConfig& guard, int steps) {
  const double start = std::max(scaled_stretch_energy(area, m, 1 + growth), guard.energy_floor);
  for (int k = 2; k <= steps; ++k)
    if (scaled_stretch_energy(area, m, 1 + growth * k) > guard.energy_ratio * start) return k;
  return -1;
}

TEST(DivergenceGuard, PositiveEnergyPastTheRatioStopsTheRolloutAtThatFrame) {
  TriMesh cloth = test::lattice_cloth(6, 6, 0.03);
  const double area = face_areas(cloth.V, cloth.F).sum();
  struct Case {
    double growth, ratio;
    bool floored;  // frame 1's energy is below the floor
  };
  for (const Case& c : {Case{0.05, 1000, false}, Case{0.01, 100, true}}) {
    RolloutInput in = hard::still_start(cloth, Effects::from_names({"gravity"}, "test"), Material{}, 40);
    in.divergence.energy_ratio = c.ratio;
    EXPECT_EQ(scaled_stretch_energy(area, in.material, 1 + c.growth) < in.divergence.energy_floor, c.floored);
    const int trip = expected_trip_frame(area, in.material, c.growth, in.divergence, in.steps);
    ASSERT_GT(trip, 2);
    ASSERT_LT(trip, in.steps);
    std::vector<int> seen;
    RolloutResult r = run_rollout(in, stretching_stepper(cloth, c.growth), PhysicsConfig{},
                                  [&](int f, const Eigen::MatrixXd&, const EnergyReport&, const PenetrationFigures* p) {
                                    seen.push_back(f);
                                    EXPECT_EQ(p, nullptr);
                                  });
    EXPECT_TRUE(r.diverged);
    EXPECT_EQ(r.diverged_at_frame, trip) << c.growth;
    // The tripping frame is finite and measured: its energy shows the blow-up.
    ASSERT_EQ(r.reports.size(), size_t(trip));
    EXPECT_EQ(seen.back(), trip);
    for (int k = 1; k <= trip; ++k)
      EXPECT_NEAR(positive_energy(r.reports[k - 1]), scaled_stretch_energy(area, in.material, 1 + c.growth * k),
                  1e-9 * scaled_stretch_energy(area, in.material, 1 + c.growth * k))
          << "frame " << k;
    EXPECT_NE(r.diverged_reason.find("positive energy"), std::string::npos) << r.diverged_reason;
    EXPECT_NE(r.diverged_reason.find(c.floored ? "floor" : "frame 1's"), std::string::npos) << r.diverged_reason;
    // Off: the same stepper runs to the end.
    in.divergence.energy_ratio = 0;
    EXPECT_FALSE(run_rollout(in, stretching_stepper(cloth, c.growth), PhysicsConfig{}).diverged);
  }
}

TEST(DivergenceGuard, ACalmReferenceRolloutRunsToTheEnd) {
  TriMesh cloth = test::lattice_cloth(5, 5, 0.03);
  RolloutInput in = hard::still_start(cloth, Effects::from_names({"gravity", "pins"}, "test"), Material{}, 30);
  RolloutResult r = run_rollout(in, reference_stepper({}), PhysicsConfig{});
  EXPECT_FALSE(r.diverged) << r.diverged_reason;
  EXPECT_EQ(r.reports.size(), 30u);
  EXPECT_TRUE(r.diverged_reason.empty());
}

TEST(DivergenceGuard, RatioIsAConfigKeyOfScenesAndEvaluation) {
  const SceneConfig scene = load_config<SceneConfig>("", {"divergence.energy_ratio=50", "divergence.energy_floor=0.01"});
  EXPECT_EQ(scene.divergence.energy_ratio, 50);
  EXPECT_EQ(scene.divergence.energy_floor, 0.01);
  EXPECT_EQ(scene_rollout_input(scene, SceneSetup{}).divergence.energy_ratio, 50);
  EXPECT_EQ(load_config<EvalConfig>("", {"divergence.energy_ratio=0"}).divergence.energy_ratio, 0);
  try {
    load_config<SceneConfig>("", {"divergence.energy_ratio=0.5"});
    ADD_FAILURE() << "a ratio below 1 must be refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("divergence.energy_ratio"), std::string::npos) << e.what();
  }
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

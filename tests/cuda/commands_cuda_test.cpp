// The commands with the network on the GPU: evaluate and simulate --device cuda report the
// CPU's figures and frames within float32 rounding, and a training run with run.device: cuda
// checkpoints, resumes where it stopped (in the process and through the CLI), and its
// checkpoint loads on the CPU.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "cuda/require_cuda.h"
#include "pb4u/model/model_file.h"
#include "pb4u/io/point_cache.h"
#include "pb4u/train/metrics_log.h"
#include "pb4u/train/trainer.h"
#include "pb4u/train/training_data.h"
#include "test_util.h"

namespace pb4u {
namespace {
namespace fs = std::filesystem;

using test::kSource;

// A tiny model trained on the CPU for a few steps (its weights matter here, not its quality).
const std::string& cpu_checkpoint() {
  static const std::string path = [] {
    const std::string out = test::temp_dir("cuda_cpu_run") + "/run";
    auto r = test::run_pb4u("-q --threads 1 train --config " + kSource + "/configs/train/tiny.yaml " +
                            "--set run.steps=6 --set run.checkpoint_every=6 --set data.dataset=" +
                            test::tiny_dataset() + " --out " + out);
    if (r.exit_code != 0) throw std::runtime_error("tiny training run: " + r.err);
    return out + "/final.pt";
  }();
  return path;
}

// Two JSON values of the same shape: the same keys, strings, booleans and nulls, and each pair
// of numbers agrees within `rel` (energies summed in float64 from float32 positions). Returns
// the number of numbers compared.
size_t expect_same_json(const nlohmann::json& cpu, const nlohmann::json& gpu, double rel,
                        const std::string& at) {
  if (cpu.is_number() && gpu.is_number()) {
    const double a = cpu.get<double>(), b = gpu.get<double>();
    EXPECT_LE(std::abs(a - b), rel * std::max(std::abs(a), std::abs(b)) + 1e-9)
        << at << ": cpu " << a << ", cuda " << b;
    return 1;
  }
  if (cpu.type() != gpu.type()) {
    ADD_FAILURE() << at << ": cpu " << cpu.dump() << ", cuda " << gpu.dump();
    return 0;
  }
  size_t numbers = 0;
  if (cpu.is_object()) {
    EXPECT_EQ(cpu.size(), gpu.size()) << at;
    for (const auto& [key, value] : cpu.items()) {
      if (!gpu.contains(key)) {
        ADD_FAILURE() << at << "/" << key << ": only on the cpu";
        continue;
      }
      numbers += expect_same_json(value, gpu.at(key), rel, at + "/" + key);
    }
  } else if (cpu.is_array()) {
    EXPECT_EQ(cpu.size(), gpu.size()) << at;
    for (size_t i = 0; i < std::min(cpu.size(), gpu.size()); ++i)
      numbers += expect_same_json(cpu[i], gpu[i], rel, at + "/" + std::to_string(i));
  } else {
    EXPECT_EQ(cpu, gpu) << at;
  }
  return numbers;
}

// Two `evaluate --format json` reports of the same shape whose figures agree within `rel`.
void expect_same_report(const std::string& cpu, const std::string& gpu, double rel) {
  EXPECT_GT(expect_same_json(nlohmann::json::parse(cpu), nlohmann::json::parse(gpu), rel, ""), 0u);
}

// Whether any method or sequence of an `evaluate --format json` report diverged.
bool any_diverged(const nlohmann::json& report) {
  for (const auto& level : report.at("levels"))
    for (const auto& [name, method] : level.at("methods").items()) {
      if (method.at("diverged").get<bool>()) return true;
      for (const auto& sequence : method.at("sequences"))
        if (sequence.at("diverged").get<bool>()) return true;
    }
  return false;
}

TEST(CudaCommands, EvaluateOnCudaReportsTheCpuFigures) {
  PB4U_REQUIRE_CUDA();
  const std::string args = "-q evaluate --checkpoint " + cpu_checkpoint() + " --config " + kSource +
                           "/configs/eval/tiny.yaml --set dataset=" + test::tiny_dataset() +
                           " --format json --device ";
  const auto cpu = test::run_pb4u(args + "cpu"), gpu = test::run_pb4u(args + "cuda");
  ASSERT_EQ(cpu.exit_code, 0) << cpu.err;
  ASSERT_EQ(gpu.exit_code, 0) << gpu.err;
  EXPECT_FALSE(any_diverged(nlohmann::json::parse(gpu.out))) << gpu.out;
  expect_same_report(cpu.out, gpu.out, 1e-2);
}

TEST(CudaCommands, SimulateOnCudaWritesTheCpuFrames) {
  PB4U_REQUIRE_CUDA();
  const std::string dir = test::temp_dir("cuda_sim");
  const std::string args = "-q simulate --checkpoint " + cpu_checkpoint() + " --scene " + kSource +
                           "/configs/scenes/hanging_cloth.yaml --set garment.resolution=8 --frames 5 " +
                           "--format none --out " + dir + "/";
  const auto cpu = test::run_pb4u(args + "cpu --device cpu"), gpu = test::run_pb4u(args + "cuda --device cuda");
  ASSERT_EQ(cpu.exit_code, 0) << cpu.err;
  ASSERT_EQ(gpu.exit_code, 0) << gpu.err;
  const auto a = read_pc2(dir + "/cpu/garment.pc2"), b = read_pc2(dir + "/cuda/garment.pc2");
  ASSERT_EQ(a.size(), 6u);  // the start frame and 5 steps
  ASSERT_EQ(b.size(), a.size());
  for (size_t f = 0; f < a.size(); ++f) EXPECT_LT((a[f] - b[f]).cwiseAbs().maxCoeff(), 1e-4) << "frame " << f;  // m
  EXPECT_GT((a.back() - a.front()).cwiseAbs().maxCoeff(), 1e-3);  // the cloth moved
}

TrainConfig cuda_config(const std::string& out, int steps) {
  return load_config<TrainConfig>(kSource + "/configs/train/tiny.yaml",
                                  {"data.dataset=" + test::tiny_dataset(), "run.out=" + out, "run.device=cuda",
                                   "run.steps=" + std::to_string(steps), "run.checkpoint_every=4"});
}

Trainer make_trainer(const TrainConfig& c, bool resume) {
  return Trainer(c, config_to_yaml(c), load_training_data(c.data), resume);
}

TEST(CudaTraining, StoppedAndResumedRunMatchesUninterruptedAndLoadsOnTheCpu) {
  PB4U_REQUIRE_CUDA();
  const std::string a_dir = test::temp_dir("cuda_train_a"), b_dir = test::temp_dir("cuda_train_b");
  Trainer a = make_trainer(cuda_config(a_dir, 8), false);
  a.run();
  {
    Trainer b = make_trainer(cuda_config(b_dir, 8), false);
    b.run(/*stop_at=*/4);
    EXPECT_EQ(b.step(), 4);
  }
  Trainer b = make_trainer(cuda_config(b_dir, 8), /*resume=*/true);
  EXPECT_EQ(b.step(), 4);
  for (const auto& p : b.model()->parameters()) ASSERT_TRUE(p.is_cuda());  // read onto the run's device
  b.run();
  EXPECT_EQ(b.step(), 8);
  auto rows = read_metrics(b_dir + "/metrics.jsonl");
  ASSERT_EQ(rows.size(), 8u);
  for (size_t i = 0; i < rows.size(); ++i) EXPECT_EQ(rows[i][0].second, double(i + 1));
  // The same samples in the same order (they depend on seed and step only); CUDA sums in no
  // fixed order, so the two runs agree up to rounding, not bit for bit.
  auto pa = a.model()->named_parameters(), pb = b.model()->named_parameters();
  for (const auto& p : pa)
    EXPECT_TRUE(torch::allclose(p.value(), pb[p.key()], 1e-3, 1e-4)) << p.key();
  auto ba = a.model()->named_buffers(), bb = b.model()->named_buffers();
  for (const auto& p : ba) EXPECT_TRUE(torch::allclose(p.value(), bb[p.key()], 1e-3, 1e-4)) << p.key();

  // Its checkpoint loads on the CPU (evaluate and export on a machine without a GPU).
  const ModelFile m = load_model_file(b_dir + "/final.pt");
  auto pm = m.model->named_parameters();
  for (const auto& p : pb) {
    ASSERT_TRUE(pm[p.key()].is_cpu()) << p.key();
    EXPECT_TRUE(torch::equal(pm[p.key()], p.value().to(torch::kCPU))) << p.key();
  }
}

TEST(CudaTraining, TrainCommandOnCudaResumes) {
  PB4U_REQUIRE_CUDA();
  const std::string out = test::temp_dir("cuda_train_cli") + "/run";
  const std::string args = "-q --threads 1 train --config " + kSource + "/configs/train/tiny.yaml " +
                           "--set run.device=cuda --set run.checkpoint_every=2 --set data.dataset=" +
                           test::tiny_dataset() + " --out " + out;
  auto r = test::run_pb4u(args + " --set run.steps=4");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out + "/checkpoints/step_00000004.pt"));
  r = test::run_pb4u(args + " --set run.steps=6 --resume");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out + "/checkpoints/step_00000006.pt"));
  auto rows = read_metrics(out + "/metrics.jsonl");
  ASSERT_EQ(rows.size(), 6u);
  for (size_t i = 0; i < rows.size(); ++i) EXPECT_EQ(rows[i][0].second, double(i + 1));
  // The run's model, trained on the GPU, evaluates on the CPU.
  r = test::run_pb4u("-q evaluate --checkpoint " + out + "/final.pt --config " + kSource +
                     "/configs/eval/tiny.yaml --set dataset=" + test::tiny_dataset() + " --set levels=[1]");
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

}  // namespace
}  // namespace pb4u

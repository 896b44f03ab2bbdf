// Checkpoints round-trip, fail cleanly on corrupt or mismatched files, and never leave
// partial files; the metrics log drops steps a resumed run will redo.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <torch/torch.h>

#include <filesystem>
#include <sstream>

#include "pb4u/model/checkpoint.h"
#include "pb4u/train/metrics_log.h"
#include "pb4u/util/error.h"
#include "test_util.h"

namespace pb4u {
namespace {
namespace fs = std::filesystem;

struct NetImpl : torch::nn::Module {
  explicit NetImpl(int width) {
    fc = register_module("fc", torch::nn::Linear(3, width));
    stat = register_buffer("stat", torch::zeros({width}));
  }
  torch::nn::Linear fc{nullptr};
  torch::Tensor stat;
};
TORCH_MODULE(Net);

std::string error_of(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Checkpoint, RoundTripsModelOptimiserStepAndRng) {
  torch::manual_seed(1);
  Net a(4);
  a->stat.fill_(2.5);
  torch::optim::Adam opt_a(a->parameters(), torch::optim::AdamOptions(1e-2));
  a->fc->forward(torch::randn({5, 3})).sum().backward();
  opt_a.step();
  std::string dir = test::temp_dir("ckpt");
  CheckpointMeta meta;
  meta.step = 17;
  meta.config_yaml = "model:\n  width: 4\n";
  meta.host_rng_state = "12345 678";
  meta.elapsed_seconds = 12.5;
  meta.skipped_steps = 2;
  save_checkpoint(checkpoint_path(dir, 17), *a, &opt_a, meta);
  torch::Tensor expected_next = torch::rand({3});  // drawn after the state was saved

  Net b(4);
  torch::optim::Adam opt_b(b->parameters(), torch::optim::AdamOptions(1e-2));
  CheckpointMeta back = load_checkpoint(checkpoint_path(dir, 17), *b, &opt_b);
  EXPECT_EQ(back.step, 17);
  EXPECT_EQ(back.config_yaml, meta.config_yaml);
  EXPECT_EQ(back.host_rng_state, meta.host_rng_state);
  EXPECT_EQ(back.elapsed_seconds, 12.5);
  EXPECT_EQ(back.skipped_steps, 2);
  EXPECT_TRUE(torch::equal(a->fc->weight, b->fc->weight));
  EXPECT_TRUE(torch::equal(a->stat, b->stat));
  EXPECT_TRUE(torch::equal(torch::rand({3}), expected_next));  // torch RNG restored
  // The optimiser continues identically.
  opt_a.zero_grad();
  opt_b.zero_grad();
  for (auto* net : {&a, &b}) (*net)->fc->forward(torch::ones({2, 3})).sum().backward();
  opt_a.step();
  opt_b.step();
  EXPECT_TRUE(torch::allclose(a->fc->weight, b->fc->weight));
  EXPECT_EQ(read_checkpoint_meta(checkpoint_path(dir, 17)).step, 17);
}

TEST(Checkpoint, CorruptTruncatedMissingAndMismatchedFailCleanly) {
  std::string dir = test::temp_dir("ckpt_bad");
  Net a(4);
  std::string good = checkpoint_path(dir, 1);
  save_checkpoint(good, *a, nullptr, {});

  std::string e = error_of([&] { read_checkpoint_meta(dir + "/missing.pt"); });
  EXPECT_NE(e.find("no such checkpoint"), std::string::npos) << e;

  std::string bytes = test::read_file(good);
  test::write_file(dir + "/trunc.pt", bytes.substr(0, bytes.size() / 2));
  e = error_of([&] { read_checkpoint_meta(dir + "/trunc.pt"); });
  EXPECT_NE(e.find(dir + "/trunc.pt"), std::string::npos) << e;

  test::write_file(dir + "/random.pt", std::string(2048, '\x7f'));
  e = error_of([&] { read_checkpoint_meta(dir + "/random.pt"); });
  EXPECT_NE(e.find("corrupt"), std::string::npos) << e;

  test::write_file(dir + "/empty.pt", "");
  e = error_of([&] { read_checkpoint_meta(dir + "/empty.pt"); });
  EXPECT_NE(e.find("empty"), std::string::npos) << e;

  Net wider(8);
  e = error_of([&] { load_checkpoint(good, *wider, nullptr); });
  EXPECT_NE(e.find("does not match"), std::string::npos) << e;
}

TEST(Checkpoint, ListLatestPruneAndNoTemporaries) {
  std::string dir = test::temp_dir("ckpt_list");
  Net a(2);
  for (int s : {5, 10, 15, 20}) save_checkpoint(checkpoint_path(dir, s), *a, nullptr, {});
  test::write_file(checkpoint_path(dir, 25) + ".tmp.999", "partial");  // a killed writer's leftover
  EXPECT_EQ(latest_checkpoint(dir), checkpoint_path(dir, 20));
  prune_checkpoints(dir, 2);
  auto left = list_checkpoints(dir);
  ASSERT_EQ(left.size(), 2u);
  EXPECT_EQ(left[0], checkpoint_path(dir, 15));
  EXPECT_EQ(latest_checkpoint(test::temp_dir("none")), "");
}

TEST(MetricsLog, ResumeDropsLaterStepsAndNaNBecomesNull) {
  std::string path = test::temp_dir("metrics") + "/metrics.jsonl";
  {
    MetricsLog log(path, -1);
    for (int s = 1; s <= 5; ++s) log.write(s, {{"loss", 1.0 / s}, {"lr", 1e-3}});
  }
  {
    MetricsLog log(path, 3);
    log.write(4, {{"loss", NAN}, {"lr", 1e-3}});
  }
  auto rows = read_metrics(path);
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[2][0].second, 3);
  EXPECT_EQ(rows[3][0].second, 4);
  EXPECT_TRUE(std::isnan(rows[3][1].second));
  std::istringstream lines(test::read_file(path));
  std::string line;
  for (int i = 0; i < 4; ++i) std::getline(lines, line);
  const nlohmann::json last = nlohmann::json::parse(line);
  EXPECT_EQ(last.at("step"), 4) << line;
  EXPECT_TRUE(last.at("loss").is_null()) << line;
}

TEST(MetricsLog, AHalfWrittenLastLineIsSkippedAndDroppedOnResume) {
  const std::string path = test::temp_dir("metrics") + "/metrics.jsonl";
  {
    MetricsLog log(path, -1);
    for (int s = 1; s <= 3; ++s) log.write(s, {{"loss", 0.123456789012 * s}});
  }
  test::write_file(path, test::read_file(path) + "{\"step\": 4, \"loss\": 0.3");  // a killed run
  auto rows = read_metrics(path);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[2][1].first, "loss");
  EXPECT_EQ(rows[2][1].second, 0.370370367);  // 9 significant digits
  {
    MetricsLog log(path, 3);
    log.write(4, {{"loss", 0.5}});
  }
  rows = read_metrics(path);
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[3][0].second, 4);
  EXPECT_EQ(rows[3][1].second, 0.5);
  // A broken line that is not the last one is an error naming the file.
  test::write_file(path, "not json\n" + test::read_file(path));
  try {
    read_metrics(path);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path + ": line 1", 0), 0u) << e.what();
  }
}

}  // namespace
}  // namespace pb4u

// Data-parallel training (issue 10) on loopback Gloo: collectives give closed-form results;
// two ranks train exactly like one process over their combined batch (through a stop and a
// group resume); a rank that never comes or dies makes the others fail within the timeout.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include "pb4u/model/checkpoint.h"
#include "pb4u/train/distributed.h"
#include "pb4u/train/metrics_log.h"
#include "pb4u/train/trainer.h"
#include "pb4u/train/training_data.h"
#include "pb4u/util/error.h"
#include "pb4u/util/runtime.h"
#include "test_util.h"

namespace pb4u {
namespace {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

using test::kSource;

// A TCP port nobody listens on now (the kernel's pick for port 0).
int free_port() {
  int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = 0;
  bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr);
  socklen_t len = sizeof addr;
  getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
  close(fd);
  return ntohs(addr.sin_port);
}

DistributedOptions options(int world, int rank, int port, double timeout = 20) {
  DistributedOptions o;
  o.world_size = world;
  o.rank = rank;
  o.master = "127.0.0.1:" + std::to_string(port);
  o.timeout_seconds = timeout;
  return o;
}

// Runs fn(rank) on `world` threads at once; rethrows the first failure.
void on_ranks(int world, const std::function<void(int)>& fn) {
  std::vector<std::string> errors(world);
  std::vector<std::thread> threads;
  for (int r = 0; r < world; ++r)
    threads.emplace_back([&, r] {
      try {
        fn(r);
      } catch (const std::exception& e) {
        errors[r] = e.what();
      }
    });
  for (auto& t : threads) t.join();
  for (int r = 0; r < world; ++r) ASSERT_EQ(errors[r], "") << "rank " << r;
}

TEST(Distributed, CollectivesGiveSumsMeansAndRootValues) {
  if (!distributed_available()) GTEST_SKIP() << "built without Gloo";
  const int port = free_port(), world = 3;
  std::vector<std::vector<double>> sums(world), means(world);
  std::vector<std::string> bytes(world);
  on_ranks(world, [&](int r) {
    DistributedGroup group(options(world, r, port));
    torch::Tensor t = torch::tensor({double(r + 1), double(10 * r)}, torch::kFloat64);
    group.all_reduce_sum(t);
    sums[r] = {t[0].item<double>(), t[1].item<double>()};
    std::vector<torch::Tensor> m{torch::full({2, 2}, float(r)), torch::Tensor(), torch::tensor({int64_t(3 * r)})};
    group.all_reduce_mean(m);
    means[r] = {m[0][1][1].item<double>(), double(m[2].item<int64_t>())};
    bytes[r] = group.broadcast_bytes(r == 0 ? std::string("from root\0!", 11) : std::string(r, 'x'));
    group.barrier();
  });
  for (int r = 0; r < world; ++r) {
    EXPECT_EQ(sums[r], (std::vector<double>{6, 30})) << r;
    EXPECT_EQ(means[r], (std::vector<double>{1, 3})) << r;
    EXPECT_EQ(bytes[r], std::string("from root\0!", 11)) << r;
  }
}

TEST(Distributed, BadOptionsAndAMissingRankAreOneLineErrors) {
  auto message = [](const DistributedOptions& o) {
    try {
      DistributedGroup g(o);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message(options(2, 2, 29500)).find("--rank"), std::string::npos);
  EXPECT_NE(message(options(0, 0, 29500)).find("--world-size"), std::string::npos);
  DistributedOptions o = options(2, 0, 29500);
  for (const char* bad : {"nohost", ":12", "host:", "host:0", "host:99999", "host:12a"}) {
    o.master = bad;
    EXPECT_NE(message(o).find("--master"), std::string::npos) << bad;
  }
  EXPECT_EQ(parse_host_port("10.0.0.2:1234", "--master"), std::make_pair(std::string("10.0.0.2"), 1234));
  if (!distributed_available()) {
    EXPECT_NE(message(options(2, 0, 29500)).find("without Gloo"), std::string::npos);
    return;
  }
  // Rank 0 alone in a group of two: an error naming the master after the timeout, no hang.
  auto t0 = Clock::now();
  std::string m = message(options(2, 0, free_port(), 1.5));
  double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  EXPECT_NE(m.find("--master"), std::string::npos) << m;
  EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  EXPECT_LT(seconds, 15) << m;
}

TrainConfig tiny_distributed_config(const std::string& out, const std::vector<std::string>& overrides = {}) {
  // Short enough for a test, long enough to see the normaliser warm-up end (10 forwards) and
  // rollouts of two steps.
  std::vector<std::string> sets{"run.steps=6", "run.checkpoint_every=3", "curriculum.steps_per_increase=2",
                                "data.dataset=" + test::tiny_dataset(), "run.out=" + out};
  sets.insert(sets.end(), overrides.begin(), overrides.end());
  return load_config<TrainConfig>(kSource + "/configs/train/tiny.yaml", sets);
}

using Tensors = std::vector<std::pair<std::string, torch::Tensor>>;
Tensors state_of(Trainer& t) {
  Tensors out;
  for (const auto& p : t.model()->named_parameters()) out.emplace_back(p.key(), p.value().detach().clone());
  for (const auto& b : t.model()->named_buffers()) out.emplace_back(b.key(), b.value().clone());
  return out;
}

// Trains `world` ranks (threads) from the data `data`, optionally stopping at `stop_at`;
// returns every rank's parameters and buffers.
std::vector<Tensors> train_ranks(int world, const TrainConfig& c, const TrainingData& data, bool resume,
                                 int64_t stop_at = -1) {
  std::vector<Tensors> states(world);
  const int port = free_port();
  on_ranks(world, [&](int r) {
    auto group = std::make_shared<DistributedGroup>(options(world, r, port));
    Trainer trainer(c, config_to_yaml(c), data, resume, group);
    trainer.run(stop_at);
    states[r] = state_of(trainer);
  });
  return states;
}

void expect_close(const Tensors& a, const Tensors& b, double tolerance, const std::string& what) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].first, b[i].first);
    EXPECT_TRUE(torch::allclose(a[i].second.to(torch::kFloat64), b[i].second.to(torch::kFloat64), tolerance, tolerance))
        << what << ": " << a[i].first << " differs by "
        << (a[i].second.to(torch::kFloat64) - b[i].second.to(torch::kFloat64)).abs().max().item<double>();
  }
}

double max_difference(const Tensors& a, const Tensors& b) {
  double d = 0;
  for (size_t i = 0; i < a.size(); ++i)
    d = std::max(d, (a[i].second.to(torch::kFloat64) - b[i].second.to(torch::kFloat64)).abs().max().item<double>());
  return d;
}

TEST(Distributed, TwoRanksTrainLikeOneProcessOverTheCombinedBatchThroughAResume) {
  if (!distributed_available()) GTEST_SKIP() << "built without Gloo";
  configure_threads(1);
  const std::string root = test::temp_dir("ddp_equal");
  TrainConfig single_cfg = tiny_distributed_config(root + "/single", {"run.batch=2"});
  TrainingData data = load_training_data(single_cfg.data);
  Trainer single(single_cfg, config_to_yaml(single_cfg), data, false);
  const Tensors initial = state_of(single);
  single.run();
  const Tensors expected = state_of(single);

  // Two ranks of batch 1, interrupted after step 3 and resumed as a group from rank 0's
  // checkpoint (rank 1 never sees the run directory).
  TrainConfig ddp_cfg = tiny_distributed_config(root + "/ddp");
  train_ranks(2, ddp_cfg, data, false, /*stop_at=*/3);
  std::vector<Tensors> ranks = train_ranks(2, ddp_cfg, data, /*resume=*/true);
  ASSERT_EQ(ranks[0].size(), expected.size());
  for (size_t i = 0; i < ranks[0].size(); ++i)
    EXPECT_TRUE(torch::equal(ranks[0][i].second, ranks[1][i].second)) << "ranks differ in " << ranks[0][i].first;
  expect_close(ranks[0], expected, 1e-6, "2 ranks vs batch 2");

  // The comparison can fail: training moved the weights, and one rank alone trains otherwise.
  EXPECT_GT(max_difference(initial, expected), 1e-4);
  TrainConfig alone_cfg = tiny_distributed_config(root + "/alone");
  Trainer alone(alone_cfg, config_to_yaml(alone_cfg), data, false);
  alone.run();
  EXPECT_GT(max_difference(state_of(alone), expected), 1e-4);

  // Rank 0's metrics are the whole batch's: the same rows as the single process's.
  auto a = read_metrics(root + "/single/metrics.jsonl"), b = read_metrics(root + "/ddp/metrics.jsonl");
  ASSERT_EQ(a.size(), 6u);
  ASSERT_EQ(b.size(), 6u);
  for (size_t i = 0; i < a.size(); ++i)
    for (size_t k = 0; k < a[i].size(); ++k)
      if (a[i][k].first != "seconds" && a[i][k].first != "step_seconds") {
        ASSERT_EQ(a[i][k].first, b[i][k].first);
        EXPECT_NEAR(a[i][k].second, b[i][k].second, 1e-6 * (1 + std::abs(a[i][k].second))) << a[i][k].first;
      }
}

// Starts a Trainer on each of two ranks (threads) with its own config; returns each rank's error.
std::vector<std::string> start_errors(const TrainConfig& c0, const TrainConfig& c1, const TrainingData& data,
                                      bool resume0 = false, bool resume1 = false) {
  std::vector<std::string> errors(2);
  const int port = free_port();
  std::vector<std::thread> ranks;
  for (int r = 0; r < 2; ++r)
    ranks.emplace_back([&, r] {
      const TrainConfig& c = r == 0 ? c0 : c1;
      try {
        Trainer trainer(c, config_to_yaml(c), data, r == 0 ? resume0 : resume1,
                        std::make_shared<DistributedGroup>(options(2, r, port, 10)));
      } catch (const Error& e) {
        errors[r] = e.what();
      }
    });
  for (auto& t : ranks) t.join();
  return errors;
}

TEST(Distributed, RanksRefuseToStartOnAnotherConfigAnOccupiedRunOrAPartialResume) {
  if (!distributed_available()) GTEST_SKIP() << "built without Gloo";
  configure_threads(1);
  const std::string root = test::temp_dir("ddp_refuse");
  TrainConfig c = tiny_distributed_config(root + "/run", {"run.checkpoint_every=1", "run.steps=1"});
  TrainingData data = load_training_data(c.data);
  TrainConfig other = c;
  other.run.seed = 1;
  for (const auto& e : start_errors(c, other, data))
    EXPECT_NE(e.find("another training config than rank 0"), std::string::npos) << e;
  EXPECT_FALSE(fs::exists(root + "/run/config.yaml"));  // a group that never started writes nothing
  // rank 0's verdict on its run directory reaches rank 1.
  Trainer(c, config_to_yaml(c), data, false).run();
  auto errors = start_errors(c, c, data);
  EXPECT_NE(errors[0].find("already holds checkpoints"), std::string::npos) << errors[0];
  EXPECT_EQ(errors[1].rfind("rank 0 could not start the run: ", 0), 0u) << errors[1];
  EXPECT_NE(errors[1].find("already holds checkpoints"), std::string::npos) << errors[1];
  for (const auto& e : start_errors(c, c, data, /*resume0=*/true, /*resume1=*/false))
    EXPECT_NE(e.find("--resume: given to 1 of 2 ranks"), std::string::npos) << e;
}

int run_script(const std::string& args, const std::string& log) {
  const std::string cmd = "PB4U=" + std::string(PB4U_BINARY) + " MASTER_PORT=" + std::to_string(free_port()) +
                          " THREADS=1 " + kSource + "/scripts/train_ddp.sh " + args + " >" + log + " 2>&1";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

TEST(Distributed, ScriptStartsTheRanksResumesThemAndReportsAFailure) {
  if (!distributed_available()) GTEST_SKIP() << "built without Gloo";
  const std::string dir = test::temp_dir("ddp_script");
  const std::string args = "2 --config " + kSource + "/configs/train/tiny.yaml --set data.dataset=" +
                           test::tiny_dataset() + " --set run.checkpoint_every=2 --out " + dir + "/run";
  ASSERT_EQ(run_script(args + " --set run.steps=4", dir + "/log1"), 0) << test::read_file(dir + "/log1");
  ASSERT_EQ(run_script(args + " --set run.steps=6 --resume", dir + "/log2"), 0) << test::read_file(dir + "/log2");
  auto rows = read_metrics(dir + "/run/metrics.jsonl");
  ASSERT_EQ(rows.size(), 6u);
  for (size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i][0].second, double(i + 1));
    for (const auto& [key, value] : rows[i])
      if (key == "samples") EXPECT_EQ(value, 2.0);
  }
  EXPECT_TRUE(fs::exists(dir + "/run/final.pt"));
  EXPECT_NE(run_script(args + " --set model.widht=3", dir + "/log3"), 0);
  EXPECT_NE(test::read_file(dir + "/log3").find("model.widht"), std::string::npos);
}

size_t lines_in(const std::string& path) {
  std::ifstream in(path);
  return static_cast<size_t>(std::count(std::istreambuf_iterator<char>(in), {}, '\n'));
}

TEST(Distributed, KillingOneRankMakesTheOtherFailWithinTheTimeout) {
  if (!distributed_available()) GTEST_SKIP() << "built without Gloo";
  const std::string dir = test::temp_dir("ddp_kill");
  const double timeout = 5;
  const std::string cmd = std::string(PB4U_BINARY) + " -q --threads 1 train --config " + kSource +
                          "/configs/train/tiny.yaml --set run.steps=100000 --set run.checkpoint_every=1"
                          " --set data.dataset=" + test::tiny_dataset() + " --out " + dir + "/run" +
                          " --world-size 2 --master 127.0.0.1:" + std::to_string(free_port()) +
                          " --timeout " + std::to_string(int(timeout)) + " --rank ";
  std::vector<pid_t> pids;
  for (int r = 0; r < 2; ++r) {
    pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      std::string run = cmd + std::to_string(r) + " >" + dir + "/out" + std::to_string(r) + " 2>" + dir + "/err" +
                        std::to_string(r);
      execl("/bin/sh", "sh", "-c", ("exec " + run).c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
    pids.push_back(pid);
  }
  // Kill rank 1 once the group has trained a few steps.
  auto deadline = Clock::now() + std::chrono::seconds(60);
  while (lines_in(dir + "/run/metrics.jsonl") < 3 && Clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_LT(Clock::now(), deadline) << test::read_file(dir + "/err0") << test::read_file(dir + "/err1");
  kill(pids[1], SIGKILL);
  waitpid(pids[1], nullptr, 0);
  auto killed = Clock::now();
  int status = 0;
  pid_t done = 0;
  while ((done = waitpid(pids[0], &status, WNOHANG)) == 0 && Clock::now() - killed < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  if (done == 0) {
    kill(pids[0], SIGKILL);
    waitpid(pids[0], &status, 0);
    FAIL() << "rank 0 still running 60 s after rank 1 died";
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - killed).count();
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_NE(WEXITSTATUS(status), 0);
  EXPECT_LT(seconds, timeout + 10);
  const std::string err = test::read_file(dir + "/err0");
  EXPECT_NE(err.find("rank 0 of 2"), std::string::npos) << err;
  EXPECT_NE(err.find("died or did not answer"), std::string::npos) << err;
  // The run directory still resumes: its newest checkpoint is whole.
  EXPECT_NO_THROW(read_checkpoint_meta(latest_checkpoint(dir + "/run/checkpoints")));
}

}  // namespace
}  // namespace pb4u

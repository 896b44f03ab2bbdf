// Cost of data-parallel training's one collective per step: the Gloo all-reduce (sum) of the
// flat float64 buffer (gradients + bookkeeping) for the quick and paper models, between ranks
// on loopback (threads of this process, each with its own group), median of repeats.
// Usage: allreduce_bench [world] [repeats]
#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>
#include <vector>

#include "pb4u/config/config_io.h"
#include "pb4u/model/pb4u_net.h"
#include "pb4u/train/distributed.h"
#include "pb4u/train/train_config.h"

int main(int argc, char** argv) {
  const int world = argc > 1 ? std::atoi(argv[1]) : 2, repeats = argc > 2 ? std::atoi(argv[2]) : 21;
  std::printf("config,parameters,world,allreduce_ms_median,allreduce_ms_min\n");
  int port = 29731;
  for (const char* name : {"quick", "paper"}) {
    auto config = pb4u::load_config<pb4u::TrainConfig>(std::string(PB4U_SOURCE_DIR) + "/configs/train/" + name + ".yaml", {});
    int64_t params = 0;
    for (const auto& p : pb4u::Pb4uNet(config.model)->parameters()) params += p.numel();
    std::vector<std::vector<double>> ms(world);
    std::vector<std::thread> ranks;
    for (int r = 0; r < world; ++r)
      ranks.emplace_back([&, r] {
        pb4u::DistributedOptions o;
        o.world_size = world;
        o.rank = r;
        o.master = "127.0.0.1:" + std::to_string(port);
        pb4u::DistributedGroup group(o);
        torch::Tensor buffer = torch::ones({params + 1000}, torch::kFloat64);
        group.all_reduce_sum(buffer);  // warm-up
        for (int i = 0; i < repeats; ++i) {
          group.barrier();
          auto t0 = std::chrono::steady_clock::now();
          group.all_reduce_sum(buffer);
          ms[r].push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        }
      });
    for (auto& t : ranks) t.join();
    std::sort(ms[0].begin(), ms[0].end());
    std::printf("%s,%lld,%d,%.2f,%.2f\n", name, static_cast<long long>(params), world, ms[0][ms[0].size() / 2], ms[0][0]);
    ++port;
  }
}

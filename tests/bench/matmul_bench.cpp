// Dense float matmul rate through torch (and so through the BLAS libtorch links):
// the yardstick for message passing (issue 8) and the BLAS set-up (docs/performance.md).
// Usage: matmul_bench [M K N] [repeats]
#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "pb4u/util/runtime.h"

int main(int argc, char** argv) {
  pb4u::ensure_fast_runtime(argc, argv);
  int64_t M = argc > 3 ? std::atoll(argv[1]) : 36000, K = argc > 3 ? std::atoll(argv[2]) : 384,
          N = argc > 3 ? std::atoll(argv[3]) : 128;
  int repeats = argc > 4 ? std::atoi(argv[4]) : 15;
  int threads = pb4u::configure_threads(0);
  torch::manual_seed(0);
  auto a = torch::randn({M, K}), b = torch::randn({K, N});
  auto c = torch::mm(a, b);  // warm-up
  std::vector<double> ms;
  for (int r = 0; r < repeats; ++r) {
    auto t0 = std::chrono::steady_clock::now();
    c = torch::mm(a, b);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(ms.begin(), ms.end());
  double median = ms[ms.size() / 2];
  double gflops = 2.0 * M * K * N / (median * 1e-3) / 1e9;
  std::printf("matmul %lldx%lldx%lld float: median %.2f ms, %.1f GFLOP/s (BLAS core %s, %d threads)\n",
              (long long)M, (long long)K, (long long)N, median, gflops,
              pb4u::blas_core_name().c_str(), threads);
  return 0;
}

#include "pb4u/util/runtime.h"

#include <dlfcn.h>
#include <malloc.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <torch/torch.h>
#include <vector>

#include "pb4u/util/resource_dir.h"

namespace pb4u {
namespace {

using CoreNameFn = char* (*)();

// The sgemm torch calls comes from libblas.so.3 (Debian alternatives). Ask that library,
// not whichever OpenBLAS happens to be loaded too (liblapack may pull in another).
CoreNameFn find_corename() {
  void* blas = dlopen("libblas.so.3", RTLD_LAZY | RTLD_NOLOAD);
  if (!blas) return nullptr;
  return reinterpret_cast<CoreNameFn>(dlsym(blas, "openblas_get_corename"));
}

bool is_avx512_core(const std::string& core) {
  return core == "SkylakeX" || core == "Cooperlake" || core == "SapphireRapids";
}

bool is_avx2_core(const std::string& core) {
  return is_avx512_core(core) || core == "Haswell" || core == "Zen";
}

// The core type to force, or "" to keep OpenBLAS's choice. Measured on this project's
// 2-core AMD EPYC VM (docs/performance.md): Prescott 59, Haswell/Zen 119, SkylakeX 190 GFLOP/s.
std::string better_core_type(const std::string& detected) {
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f") && !is_avx512_core(detected)) return "SkylakeX";
  if (__builtin_cpu_supports("avx2") && !is_avx2_core(detected)) return "Haswell";
  return "";
}

// OMP_WAIT_POLICY set when the user has none (see ensure_fast_runtime).
constexpr const char* kDefaultOmpWaitPolicy = "PASSIVE";
// libgomp's spin before a passive thread sleeps (GOMP_SPINCOUNT overrides the policy's 0).
constexpr const char* kDefaultSpinCount = "1000";
// Blocks below this size come from (and return to) the heap, not mmap (see tune_allocator).
constexpr int kMallocKeepBytes = 1 << 30;
bool allocator_tuned = false;

}  // namespace

std::string blas_core_name() {
  CoreNameFn fn = find_corename();
  if (!fn) return "reference";
  const char* name = fn();
  return name ? std::string(name) : std::string("unknown");
}

void ensure_fast_runtime(int argc, char** argv) {
  if (const char* off = std::getenv("PB4U_NO_REEXEC"); off && *off && std::strcmp(off, "0")) return;
  bool changed = false;
  // A user's own setting is kept; after our re-exec both variables are set, so this runs once.
  if (!std::getenv("OPENBLAS_CORETYPE")) {
    const std::string core = blas_core_name();
    const std::string best = core == "reference" ? "" : better_core_type(core);
    if (!best.empty()) {
      ::setenv("OPENBLAS_CORETYPE", best.c_str(), 1);
      changed = true;
    }
  }
  // libgomp spins idle threads for ~300K iterations between parallel regions. The network runs
  // hundreds of small regions per frame, and whenever another process wants a core the
  // spinners steal it: measured 200x slower frames on a loaded 2-core machine
  // (docs/performance.md). Passive threads sleep, but only after a short spin: waking a
  // sleeping thread for every small region made a 2-thread training step 1.7x slower than
  // spinning 1000 iterations first, which costs 1.5x where another process takes a core.
  if (!std::getenv("OMP_WAIT_POLICY")) {
    ::setenv("OMP_WAIT_POLICY", kDefaultOmpWaitPolicy, 1);
    if (!std::getenv("GOMP_SPINCOUNT")) ::setenv("GOMP_SPINCOUNT", kDefaultSpinCount, 1);
    changed = true;
  }
  if (!changed) return;
  std::vector<char*> args(argv, argv + argc);
  args.push_back(nullptr);
  ::execv("/proc/self/exe", args.data());
  // execv only returns on failure: carry on with the defaults.
}

void tune_allocator() {
  if (const char* off = std::getenv("PB4U_DEFAULT_MALLOC"); off && *off && std::strcmp(off, "0")) return;
  // glibc serves multi-MB blocks with mmap and unmaps them on free, so every message-passing
  // layer page-faults its output afresh; keeping freed memory in the heap avoids that.
  allocator_tuned = mallopt(M_MMAP_THRESHOLD, kMallocKeepBytes) == 1 && mallopt(M_TRIM_THRESHOLD, kMallocKeepBytes) == 1;
}

int configure_threads(int requested) {
  int n = requested > 0 ? requested : static_cast<int>(std::thread::hardware_concurrency());
  if (n <= 0) n = 1;
  torch::set_num_threads(n);
  return torch::get_num_threads();
}

void log_runtime_info() {
  const char* wait = std::getenv("OMP_WAIT_POLICY");
  const char* spin = std::getenv("GOMP_SPINCOUNT");
  spdlog::info("runtime: BLAS core {}, {} torch threads (OpenMP wait policy {}, spin {}), malloc {}, libtorch {}",
               blas_core_name(), torch::get_num_threads(), wait ? wait : "default", spin ? spin : "default",
               allocator_tuned ? "tuned" : "default", TORCH_VERSION);
  const std::string resources = resource_dir();
  spdlog::debug("resources (scripts, configs, data): {}",
                resources.empty() ? "none found beside the binary (set PB4U_DATA_DIR)" : resources);
}

}  // namespace pb4u

// Device names from configs and --device: cpu always works; cuda works exactly when libtorch
// sees a GPU, and is otherwise a one-line error naming the key, never a crash.
#include <gtest/gtest.h>
#include <torch/cuda.h>

#include "pb4u/util/device.h"
#include "pb4u/util/error.h"
#include "test_util.h"

namespace pb4u {
namespace {

std::string error_of(const std::string& name, const std::string& key) {
  try {
    resolve_device(name, key);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Device, CpuAlwaysCudaOnlyWithAGpuOtherNamesNever) {
  EXPECT_EQ(resolve_device("cpu", "run.device"), torch::Device(torch::kCPU));
  for (const char* bad : {"gpu", "", "CUDA", "cuda0", "cpu:0"}) {
    const std::string e = error_of(bad, "run.device");
    EXPECT_EQ(e, "run.device: expected cpu, cuda or cuda:N, got '" + std::string(bad) + "'") << bad;
  }
  // A malformed index is the same error with or without a GPU (the form is checked first).
  for (const char* bad : {"cuda:", "cuda:x", "cuda:-1", "cuda:0x", "cuda:1234"}) {
    const std::string e = error_of(bad, "run.device");
    EXPECT_EQ(e, "run.device: expected cpu, cuda or cuda:N, got '" + std::string(bad) + "'") << bad;
  }
  if (torch::cuda::is_available()) {
    EXPECT_EQ(resolve_device("cuda", "--device"), torch::Device(torch::kCUDA, 0));
    EXPECT_EQ(resolve_device("cuda:0", "--device"), torch::Device(torch::kCUDA, 0));
    const std::string e = error_of("cuda:999", "--device");
    EXPECT_EQ(e.rfind("--device: cuda:999 requested but there are ", 0), 0u) << e;
  } else {
    for (const char* name : {"cuda", "cuda:0", "cuda:999"}) {
      const std::string e = error_of(name, "--device");
      EXPECT_EQ(e.rfind("--device: cuda requested", 0), 0u) << e;
      EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    }
  }
}

TEST(Device, EvaluateOnAMissingGpuIsAOneLineError) {
  if (torch::cuda::is_available()) GTEST_SKIP() << "this machine has a GPU";
  auto r = test::run_pb4u("-q evaluate --device cuda --config " + std::string(PB4U_SOURCE_DIR) +
                          "/configs/eval/tiny.yaml --method reference");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--device: cuda requested"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace pb4u

// -v prints each solve's summary line; -vv also each solver iteration (what the step was, what
// cut it short, the energy's decrease), for reading where a solve spends its iterations.
#include <gtest/gtest.h>

#include "test_util.h"

namespace pb4u {
namespace {

TEST(Verbosity, DoubleVerbosePrintsEverySolverIteration) {
  const std::string dir = test::temp_dir("verbosity");
  const std::string scene = std::string(test::kSource) + "/configs/scenes/hanging_cloth.yaml";
  auto run = [&](const std::string& flag, const std::string& out) {
    return test::run_pb4u(flag + " --threads 1 simulate --method reference --scene " + scene +
                          " --frames 1 --set garment.resolution=5 --format none --preview off --out " + dir + "/" + out);
  };
  const test::CommandResult debug = run("-v", "v"), trace = run("-vv", "vv");
  ASSERT_EQ(debug.exit_code, 0) << debug.err;
  ASSERT_EQ(trace.exit_code, 0) << trace.err;
  EXPECT_NE(debug.err.find("solver step:"), std::string::npos) << debug.err;
  EXPECT_EQ(debug.err.find("iteration 0:"), std::string::npos) << debug.err;
  EXPECT_NE(trace.err.find("  iteration 0: step "), std::string::npos) << trace.err;
  EXPECT_NE(trace.err.find("of it feasible (nothing cut it)"), std::string::npos) << trace.err;
  EXPECT_NE(trace.err.find("solver step:"), std::string::npos) << trace.err;
}

}  // namespace
}  // namespace pb4u

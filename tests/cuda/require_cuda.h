#pragma once
// The cuda tests (ctest -L cuda) run where libtorch sees a GPU and are skipped, saying why,
// everywhere else (a CPU-only libtorch such as Debian's, or a machine without a GPU).
#include <gtest/gtest.h>
#include <torch/cuda.h>

#define PB4U_REQUIRE_CUDA()                                                                          \
  if (!torch::cuda::is_available())                                                                  \
  GTEST_SKIP() << "no CUDA device (a CPU-only libtorch, or no GPU on this machine): see docs/cuda.md"

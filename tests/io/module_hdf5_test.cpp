// Portable HDF5 model files round-trip and reject mismatched or corrupt files.
#include <gtest/gtest.h>
#include <torch/torch.h>

#include "pb4u/io/module_hdf5.h"
#include "pb4u/util/error.h"
#include "test_util.h"

namespace pb4u {
namespace {

struct TinyImpl : torch::nn::Module {
  explicit TinyImpl(int width) {
    a = register_module("a", torch::nn::Linear(3, width));
    b = register_module("b", torch::nn::Sequential(torch::nn::Linear(width, 2), torch::nn::LayerNorm(
                                                       torch::nn::LayerNormOptions({2}))));
    count = register_buffer("count", torch::zeros({1}, torch::kInt64));
    mean = register_buffer("mean", torch::zeros({width}, torch::kFloat64));
  }
  torch::nn::Linear a{nullptr};
  torch::nn::Sequential b{nullptr};
  torch::Tensor count, mean;
};
TORCH_MODULE(Tiny);

TEST(ModuleHdf5, RoundTripGivesIdenticalTensorsAndAttributes) {
  torch::manual_seed(3);
  Tiny m(5);
  m->count.fill_(42);
  m->mean.uniform_();
  std::string path = test::temp_dir("h5") + "/model.h5";
  save_module_hdf5(path, *m, {{"format", "pb4u-model"}, {"config", "model:\n  kind: pb4u\n"}});
  Tiny n(5);
  load_module_hdf5(path, *n);
  for (const auto& p : m->named_parameters()) EXPECT_TRUE(torch::equal(p.value(), n->named_parameters()[p.key()])) << p.key();
  for (const auto& b : m->named_buffers()) EXPECT_TRUE(torch::equal(b.value(), n->named_buffers()[b.key()])) << b.key();
  auto attrs = read_hdf5_attributes(path);
  EXPECT_EQ(attrs["format"], "pb4u-model");
  EXPECT_EQ(attrs["config"], "model:\n  kind: pb4u\n");
  auto x = torch::randn({4, 3});
  EXPECT_TRUE(torch::equal(m->b->forward(m->a->forward(x)), n->b->forward(n->a->forward(x))));
}

TEST(ModuleHdf5, MismatchedShapeLeavesModuleUntouched) {
  std::string path = test::temp_dir("h5") + "/model.h5";
  save_module_hdf5(path, *Tiny(5), {});
  Tiny wide(6);
  torch::Tensor before = wide->a->weight.clone();
  try {
    load_module_hdf5(path, *wide);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("does not match"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  EXPECT_TRUE(torch::equal(before, wide->a->weight));
}

TEST(ModuleHdf5, CorruptAndMissingFiles) {
  std::string dir = test::temp_dir("h5bad");
  test::write_file(dir + "/junk.h5", std::string(1000, 'x'));
  EXPECT_THROW(read_hdf5_attributes(dir + "/junk.h5"), Error);
  EXPECT_THROW(read_hdf5_attributes(dir + "/none.h5"), Error);
  save_module_hdf5(dir + "/good.h5", *Tiny(2), {});
  std::string bytes = test::read_file(dir + "/good.h5");
  test::write_file(dir + "/trunc.h5", bytes.substr(0, bytes.size() / 3));
  Tiny t(2);
  EXPECT_THROW(load_module_hdf5(dir + "/trunc.h5", *t), Error);
}

}  // namespace
}  // namespace pb4u

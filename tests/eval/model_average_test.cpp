// Weight averaging (`pb4u export` with several --checkpoint, eval/model_average.h): the file
// holds the weighted mean of the parameters and the first model's buffers; models that differ
// in shape or in their normaliser statistics, and weights that do not sum to 1, are refused
// naming the file or the option, and nothing is written.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "pb4u/eval/model_average.h"
#include "pb4u/model/model_file.h"
#include "pb4u/io/module_hdf5.h"
#include "pb4u/model/checkpoint.h"
#include "pb4u/train/trainer.h"
#include "pb4u/train/training_data.h"
#include "pb4u/util/error.h"
#include "pb4u/util/runtime.h"
#include "test_util.h"

namespace pb4u {
namespace {
namespace fs = std::filesystem;

// Checkpoints of one tiny run, oldest first: steps 40, 50, 60 and 70, after the normalisers'
// warm-up (10 calls each).
const std::vector<std::string>& tiny_run_checkpoints() {
  static const std::vector<std::string> paths = [] {
    configure_threads(1);
    const std::string out = test::temp_dir("average_tinyrun");
    TrainConfig c = load_config<TrainConfig>(std::string(PB4U_SOURCE_DIR) + "/configs/train/tiny.yaml",
                                             {"data.dataset=" + test::tiny_dataset(), "run.out=" + out,
                                              "run.steps=70", "run.checkpoint_every=10", "run.keep_checkpoints=4"});
    Trainer trainer(c, config_to_yaml(c), load_training_data(c.data), false);
    trainer.run();
    return list_checkpoints(out + "/checkpoints");
  }();
  return paths;
}

TEST(ModelAverage, WeightedMeanOfTheParametersWithTheFirstModelsBuffers) {
  const auto& ckpts = tiny_run_checkpoints();
  ASSERT_EQ(ckpts.size(), 4u);
  const ModelFile a = load_model_file(ckpts[2]), b = load_model_file(ckpts[3]);  // steps 60, 70
  const ModelFile mean = average_models({a, b}, {0.25, 0.75});
  EXPECT_EQ(mean.step, a.step);
  EXPECT_EQ(mean.config_yaml, a.config_yaml);
  auto pa = a.model->named_parameters(), pb = b.model->named_parameters();
  double moved = 0;
  for (const auto& p : mean.model->named_parameters()) {
    const torch::Tensor expected = 0.25 * pa[p.key()] + 0.75 * pb[p.key()];
    EXPECT_TRUE(torch::allclose(p.value(), expected, 1e-6, 1e-7)) << p.key();
    moved += (pa[p.key()] - pb[p.key()]).abs().sum().item<double>();
  }
  EXPECT_GT(moved, 0.0);  // the two checkpoints differ, so the mean is a third model
  auto ba = a.model->named_buffers();
  for (const auto& buf : mean.model->named_buffers()) EXPECT_TRUE(torch::equal(buf.value(), ba[buf.key()])) << buf.key();
  EXPECT_DOUBLE_EQ(mean.model->mean_edge_length_base(), a.model->mean_edge_length_base());
  // The inputs are untouched (the mean is a new module, not a's).
  EXPECT_FALSE(torch::allclose(mean.model->named_parameters().begin()->value(), pa.begin()->value()));

  // Equal weights by default; a model extrapolated from itself is itself.
  const ModelFile half = average_models({a, b}, {});
  for (const auto& p : half.model->named_parameters())
    EXPECT_TRUE(torch::allclose(p.value(), 0.5 * (pa[p.key()] + pb[p.key()]), 1e-6, 1e-7)) << p.key();
  const ModelFile same = average_models({a, a}, {1.5, -0.5});
  for (const auto& p : same.model->named_parameters())
    EXPECT_TRUE(torch::allclose(p.value(), pa[p.key()], 1e-5, 1e-6)) << p.key();
}

TEST(ModelAverage, ExportWritesTheAverageThatLoadsBack) {
  const auto& ckpts = tiny_run_checkpoints();
  const std::string dir = test::temp_dir("average_export");
  // The same weights with other normaliser statistics (as a checkpoint inside the warm-up has).
  {
    ModelFile warming = load_model_file(ckpts[1]);
    torch::NoGradGuard no_grad;
    for (auto& buf : warming.model->named_buffers())
      if (buf.key().find("sum_squares") != std::string::npos) buf.value().mul_(1.5);
    export_model_file(warming, dir + "/warming.h5");
  }
  auto r = test::run_pb4u("-q export --checkpoint " + ckpts[2] + " --checkpoint " + dir + "/warming.h5 --checkpoint " +
                          ckpts[3] + " --weights 0.5,0,0.5 --out " + dir + "/mean.h5");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(dir + "/warming.h5"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("normaliser statistics"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/mean.h5"));

  r = test::run_pb4u("-q export --checkpoint " + ckpts[2] + " --checkpoint " + ckpts[3] + " --weights 0.5,0.5 --out " +
                     dir + "/mean.h5 --set update_scaling=detail");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const ModelFile loaded = load_model_file(dir + "/mean.h5");
  const ModelFile direct = average_models({load_model_file(ckpts[2]), load_model_file(ckpts[3])}, {});
  EXPECT_EQ(loaded.config.update_scaling, "detail");
  auto pd = direct.model->named_parameters();
  for (const auto& p : loaded.model->named_parameters()) EXPECT_TRUE(torch::equal(p.value(), pd[p.key()])) << p.key();
  EXPECT_NE(read_hdf5_attributes(dir + "/mean.h5").at("source").find(ckpts[3]), std::string::npos);
}

TEST(ModelAverage, RefusesWhatDoesNotMixNamingTheFileOrOption) {
  const auto& ckpts = tiny_run_checkpoints();
  const std::string dir = test::temp_dir("average_bad");
  const ModelFile a = load_model_file(ckpts[3]);
  // Weights: not summing to 1, or not one per model.
  for (const std::string& w : {std::string("0.5,0.6"), std::string("1"), std::string("0.5,nan")}) {
    auto r = test::run_pb4u("-q export --checkpoint " + ckpts[2] + " --checkpoint " + ckpts[3] + " --weights " + w +
                            " --out " + dir + "/out.h5");
    EXPECT_NE(r.exit_code, 0) << w;
    EXPECT_NE(r.err.find("--weights"), std::string::npos) << w << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir + "/out.h5"));
  }
  // Another width: shapes differ.
  ModelConfig wide = a.config;
  wide.latent = a.config.latent * 2;
  ModelFile other{Pb4uNet(wide), wide, config_to_yaml(wide), dir + "/wide.h5", "export", 0};
  other.model->calibrate(a.model->mean_edge_length_base());
  try {
    average_models({a, other}, {});
    ADD_FAILURE() << "a model of another width was averaged";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(dir + "/wide.h5"), std::string::npos) << e.what();
  }
  // MGN and Pb4U do not mix.
  ModelConfig mgn = a.config;
  mgn.kind = "mgn";
  ModelFile fixed{Pb4uNet(mgn), mgn, config_to_yaml(mgn), dir + "/mgn.h5", "export", 0};
  EXPECT_THROW(average_models({a, fixed}, {}), Error);
}

}  // namespace
}  // namespace pb4u

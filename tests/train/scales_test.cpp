// data.scales: a training sample's whole scene (garment, body, motion, pins) scaled by one of
// the factors, with K's sampled range scaled by 1 / c; a bad factor names the key.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "pb4u/train/trainer.h"
#include "pb4u/train/training_data.h"
#include "pb4u/util/error.h"
#include "pb4u/util/runtime.h"
#include "test_util.h"

namespace pb4u {
namespace {

TrainConfig scaled_config(const std::string& tag, const std::string& scales) {
  std::vector<std::string> sets = {"data.dataset=" + test::tiny_dataset(), "run.out=" + test::temp_dir(tag),
                                   "data.scales=" + scales, "effects.p_gravity=1",
                                   // frozen weights: both runs step with the same network
                                   "optim.lr=1e-12", "optim.lr_final=1e-12"};
  return load_config<TrainConfig>(test::kSource + "/configs/train/tiny.yaml", sets);
}

double term(const StepResult& s, const std::string& name) {
  for (const auto& [n, v] : s.terms)
    if (n == name) return v;
  ADD_FAILURE() << "no term " << name;
  return 0;
}

// With one factor nothing extra is drawn, so [1] and [0.5] train on the same samples: the
// scaled one's garment has a quarter of the mass at half the height, so gravity's energy
// (sum m g y, measured from y = 0) is ~1/8 of it (the network's step adds a dt^2 ~ 1 cm).
TEST(Scales, AScaledSampleIsTheSameSceneSmaller) {
  configure_threads(1);
  TrainConfig plain_config = scaled_config("scales_plain", "[1]");
  TrainConfig half_config = scaled_config("scales_half", "[0.5]");
  Trainer plain(plain_config, config_to_yaml(plain_config), load_training_data(plain_config.data), false);
  Trainer half(half_config, config_to_yaml(half_config), load_training_data(half_config.data), false);
  for (int i = 0; i < 6; ++i) {
    const StepResult a = plain.train_step(), b = half.train_step();
    ASSERT_TRUE(std::isfinite(a.loss) && std::isfinite(b.loss)) << i;
    const double ratio = term(b, "gravity") / term(a, "gravity");
    EXPECT_NEAR(ratio, 0.125, 0.125 * 0.1) << "step " << i;
  }
}

// K is drawn from [0, 2 K_base / c]: at c = 0.25 up to 8 K_base, never above.
TEST(Scales, KsRangeGrowsAsTheSceneShrinks) {
  configure_threads(1);
  TrainConfig c = scaled_config("scales_k", "[0.25]");
  c.run.steps = 30;
  Trainer trainer(c, config_to_yaml(c), load_training_data(c.data), false);
  int64_t largest = 0;
  for (int i = 0; i < c.run.steps; ++i) largest = std::max(largest, trainer.train_step().K);
  EXPECT_GT(largest, 2 * c.model.k_base);
  EXPECT_LE(largest, 8 * c.model.k_base);
}

TEST(Scales, ABadFactorNamesTheKey) {
  for (const std::string bad : {"[0]", "[-0.5]", "[]", "[1, 20]"}) {
    try {
      TrainConfig c = scaled_config("scales_bad", bad);
      Trainer trainer(c, config_to_yaml(c), load_training_data(c.data), false);
      ADD_FAILURE() << bad << " accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("data.scales"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace pb4u

// data.speedups: every training motion is also trained on played faster, resampled so that a
// 1/30 s step covers `speedup` of its frames; a bad speed-up names the key.
#include <gtest/gtest.h>

#include "pb4u/train/training_data.h"
#include "pb4u/util/error.h"
#include "test_util.h"

namespace pb4u {
namespace {

TrainDataConfig tiny_data(std::vector<double> speedups) {
  TrainDataConfig c;
  c.dataset = test::tiny_dataset();
  c.speedups = std::move(speedups);
  return c;
}

TEST(Speedups, EachMotionAlsoPlaysFasterOnItsOwnBody) {
  const TrainingData plain = load_training_data(tiny_data({}));
  const TrainingData fast = load_training_data(tiny_data({2.0}));
  ASSERT_FALSE(plain.motions.empty());
  ASSERT_EQ(fast.motions.size(), 2 * plain.motions.size());
  EXPECT_EQ(fast.garments.size(), plain.garments.size());
  for (size_t i = 0; i < plain.motions.size(); ++i) {
    const Motion& m = plain.motions[i];
    const Motion& recorded = fast.motions[2 * i];
    const Motion& doubled = fast.motions[2 * i + 1];
    EXPECT_EQ(fast.motion_body[2 * i + 1], plain.motion_body[i]);
    EXPECT_EQ(recorded.num_frames(), m.num_frames());
    EXPECT_DOUBLE_EQ(doubled.fps, m.fps);  // stepped at the same rate...
    EXPECT_EQ(doubled.num_frames(), (m.num_frames() - 1) / 2 + 1);  // ...over half the frames
    // Frame k of the fast motion is frame 2k of the recorded one.
    for (int k = 0; k < doubled.num_frames(); k += 3) {
      EXPECT_NEAR((doubled.frames[k].root - m.frames[2 * k].root).norm(), 0.0, 1e-9) << k;
      for (size_t j = 0; j < m.frames[2 * k].rotations.size(); ++j)
        EXPECT_NEAR(doubled.frames[k].rotations[j].angularDistance(m.frames[2 * k].rotations[j]), 0.0, 1e-6) << k;
    }
  }
}

TEST(Speedups, ANonPositiveSpeedupNamesTheKey) {
  for (double bad : {0.0, -1.5}) {
    try {
      load_training_data(tiny_data({bad}));
      ADD_FAILURE() << bad << " accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("data.speedups"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace pb4u

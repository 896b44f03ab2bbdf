// BVH import: the CMU samples, 30 fps resampling and malformed files.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "pb4u/body/bvh.h"
#include "pb4u/body/humanoid.h"
#include "pb4u/util/error.h"

using namespace pb4u;

namespace {

const std::string kSample = std::string(PB4U_MOCAP_DATA) + "/cmu_131_01.bvh";

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Counts "ROOT"/"JOINT" keywords: an independent joint count.
int count_joints(const std::string& text) {
  std::istringstream in(text);
  std::string word;
  int n = 0;
  while (in >> word) n += word == "ROOT" || word == "JOINT";
  return n;
}

const char* kTiny = R"(HIERARCHY
ROOT Hips
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation
  JOINT Spine
  {
    OFFSET 0 1 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    End Site
    {
      OFFSET 0 1 0
    }
  }
}
MOTION
Frames: 3
Frame Time: 0.5
0 0 0 0 0 0 0 0 0
1 2 3 0 90 0 0 0 0
2 4 6 0 0 0 90 0 0
)";

}  // namespace

TEST(Bvh, CmuSampleParsesAndResamplesTo30Fps) {
  const std::string text = read_text(kSample);
  ASSERT_FALSE(text.empty()) << kSample;
  const BvhFile raw = parse_bvh(text, kSample);
  EXPECT_EQ(raw.skeleton.num_joints(), count_joints(text));
  EXPECT_EQ(raw.source_frames, 995);
  EXPECT_NEAR(raw.source_fps, 120.0, 0.1);
  const BvhFile bvh = read_bvh(kSample, 30.0);
  EXPECT_DOUBLE_EQ(bvh.motion.fps, 30.0);
  const double duration = (raw.source_frames - 1) / raw.source_fps;
  EXPECT_EQ(bvh.motion.num_frames(), static_cast<int>(std::floor(duration * 30.0 + 1e-6)) + 1);
  // Frame time 0.008333 s is 120.005 fps, so output frame k sits at source frame ~4k.
  for (int k : {0, 10, 100}) {
    const double s = k / 30.0 * raw.source_fps;
    const Pose& a = raw.motion.frames[static_cast<int>(std::round(s))];
    EXPECT_LT((bvh.motion.frames[k].root - a.root).norm(), 0.01);
  }
  // A CMU skeleton is a humanoid the mannequin can be built from.
  EXPECT_NO_THROW(find_humanoid_joints(bvh.skeleton, kSample));
}

TEST(Bvh, ChannelOrderAndRootTranslationFollowTheFile) {
  const BvhFile b = parse_bvh(kTiny, "tiny.bvh");
  ASSERT_EQ(b.skeleton.num_joints(), 2);
  EXPECT_EQ(b.skeleton.parents[1], 0);
  EXPECT_EQ(b.motion.frames[1].root, Eigen::Vector3d(1, 2, 3));
  // Frame 1: Yrotation 90 on the root maps x to -z.
  const Eigen::Vector3d x = b.motion.frames[1].rotations[0] * Eigen::Vector3d::UnitX();
  EXPECT_LT((x - Eigen::Vector3d(0, 0, -1)).norm(), 1e-12);
  // Frame 2: the spine's first channel is Zrotation 90, mapping x to y.
  const Eigen::Vector3d y = b.motion.frames[2].rotations[1] * Eigen::Vector3d::UnitX();
  EXPECT_LT((y - Eigen::Vector3d(0, 1, 0)).norm(), 1e-12);
  // 2 fps resampled to 4 fps: 1 s of motion gives 5 frames, midpoints interpolated.
  const Motion m = resample_motion(b.motion, 4.0);
  ASSERT_EQ(m.num_frames(), 5);
  EXPECT_LT((m.frames[1].root - Eigen::Vector3d(0.5, 1, 1.5)).norm(), 1e-12);
}

TEST(Bvh, MalformedFilesGiveOneLineErrorsNamingTheFile) {
  std::string text = kTiny;
  auto expect_error = [](const std::string& t, const std::string& needle) {
    try {
      parse_bvh(t, "bad.bvh");
      ADD_FAILURE() << "no error for " << needle;
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind("bad.bvh: ", 0), 0u) << what;
      EXPECT_NE(what.find(needle), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos);
    }
  };
  expect_error(text.substr(0, text.size() - 20), "frames");            // truncated data
  expect_error(std::string(text).replace(text.find("Zrotation Xrotation"), 9, "Wrotation"),
               "unknown channel");
  expect_error(std::string(text).replace(text.find("OFFSET 0 1 0"), 12, "OFFSET 0 x 0"),
               "expected a number");
  expect_error(std::string(text).replace(text.find("MOTION"), 6, "MOTIONS"), "MOTION");
  expect_error(text + " 7", "extra values");
  expect_error("", "empty");
  EXPECT_THROW(read_bvh("/nonexistent/file.bvh"), Error);
  // Hostile headers: more frames than values, a frame lasting a day, no channels,
  // joints nested deeper than any skeleton.
  const size_t frames = text.find("Frames:"), frame_time = text.find("Frame Time:");
  expect_error(std::string(text).replace(frames, text.find('\n', frames) - frames, "Frames: 7000"),
               "frames its header declares");
  expect_error(std::string(text).replace(frame_time, text.find('\n', frame_time) - frame_time, "Frame Time: 86400"),
               "more than 3600");
  std::string deep = "HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\nCHANNELS 3 Xrotation Yrotation Zrotation\n";
  for (int i = 0; i < 1100; ++i) deep += "JOINT j\n{\nOFFSET 0 0 0\nCHANNELS 0\n";
  expect_error(deep, "nested more than");
  expect_error("HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\nCHANNELS 0\n}\nMOTION\nFrames: 1000\nFrame Time: 0.001\n",
               "no joint has channels");
}

// PC2 caches round-trip and reject truncated files.
#include <gtest/gtest.h>

#include "pb4u/io/point_cache.h"
#include "pb4u/util/error.h"
#include "test_util.h"

namespace pb4u {
namespace {

TEST(PointCache, RoundTripAndHeaderLayout) {
  std::vector<Eigen::MatrixXd> frames;
  for (int t = 0; t < 4; ++t) frames.push_back(Eigen::MatrixXd::Random(7, 3) + Eigen::MatrixXd::Constant(7, 3, t));
  std::string path = test::temp_dir("pc2") + "/g.pc2";
  write_pc2(path, frames);
  std::string bytes = test::read_file(path);
  ASSERT_EQ(bytes.size(), 32u + 4 * 7 * 12);
  EXPECT_EQ(bytes.substr(0, 11), "POINTCACHE2");
  auto back = read_pc2(path);
  ASSERT_EQ(back.size(), 4u);
  for (int t = 0; t < 4; ++t) EXPECT_TRUE(back[t].isApprox(frames[t], 1e-6));
  test::write_file(path, bytes.substr(0, bytes.size() - 5));
  EXPECT_THROW(read_pc2(path), Error);
}

}  // namespace
}  // namespace pb4u

#include <filesystem>

#include "pb4u/io/mesh_io.h"
#include "pb4u/sim/rollout_writer.h"

namespace pb4u {
namespace {

TEST(RolloutWriter, WritesEveryFrameInEveryFormat) {
  TriMesh g = test::grid_mesh(2), b = test::grid_mesh(1, 3.0);
  std::string dir = test::temp_dir("rollout");
  RolloutWriter w(dir, g.F, b.F, RolloutOutputs{"ply"});
  for (int t = 0; t < 3; ++t) {
    Eigen::MatrixXd x = g.V;
    x.col(1).array() -= 0.1 * t;
    w.add_frame(x, b.V, {{"stretch", 0.5 * t}, {"total", 1.0 * t}});
  }
  auto files = w.finish();
  EXPECT_EQ(files.size(), 3u * 2 + 2 + 1 + 1 + 1);  // frames, PC2s, scene.usda, h5, csv
  for (const auto& f : files) EXPECT_TRUE(std::filesystem::exists(f)) << f;
  EXPECT_EQ(read_pc2(dir + "/garment.pc2").size(), 3u);
  EXPECT_NEAR(read_pc2(dir + "/garment.pc2")[2](0, 1), -0.2, 1e-6);
  EXPECT_EQ(read_mesh(frame_file(dir, "garment", 2, "ply")).num_faces(), g.num_faces());
  EXPECT_EQ(test::read_file(dir + "/energies.csv"), "frame,stretch,total\n0,0,0\n1,0.5,1\n2,1,2\n");
}

TEST(RolloutWriter, NoBodyMeansNoBodyFiles) {
  TriMesh g = test::grid_mesh(1);
  std::string dir = test::temp_dir("rollout_nobody");
  RolloutWriter w(dir, g.F, Eigen::MatrixXi(0, 3), RolloutOutputs{});
  w.add_frame(g.V, Eigen::MatrixXd(), {{"stretch", 0.0}});
  w.finish();
  EXPECT_FALSE(std::filesystem::exists(dir + "/body.pc2"));
  EXPECT_EQ(test::read_file(dir + "/scene.usda").find("def Mesh \"Body\""), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(frame_file(dir, "body", 0, "obj")));
  EXPECT_TRUE(std::filesystem::exists(frame_file(dir, "garment", 0, "obj")));
}

}  // namespace
}  // namespace pb4u

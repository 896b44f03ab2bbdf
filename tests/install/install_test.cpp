// `cmake --install` gives a pb4u that runs from its prefix: the install is moved to another
// directory (so nothing can be found where it was installed, nor through the build tree) and
// simulates a scene there, its preview drawn by the installed scripts.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "pb4u/util/plot_script.h"
#include "pb4u/util/remove_tree.h"
#include "pb4u/util/subprocess.h"
#include "test_util.h"

namespace pb4u {
namespace {
namespace fs = std::filesystem;

TEST(Install, AMovedPrefixSimulatesWithItsPreview) {
  const std::string build_dir = fs::path(PB4U_BINARY).parent_path().string();
  const std::string base = test::temp_dir("install");
  const std::string installed = base + "/installed", moved = base + "/moved";
  ASSERT_EQ(run_process({"cmake", "--install", build_dir, "--prefix", installed}, base + "/install.log"), 0)
      << test::read_file(base + "/install.log");
  for (const char* file : {"bin/pb4u", "share/pb4u/scripts/plot_preview.py", "share/pb4u/configs/scenes/hanging_cloth.yaml",
                           "share/pb4u/data/pretrained/pb4u.h5", "share/pb4u/data/mocap/cmu_131_01.bvh"})
    EXPECT_TRUE(fs::exists(installed + "/" + file)) << file;
  fs::rename(installed, moved);

  ::unsetenv("PB4U_DATA_DIR");  // a user's setting would point elsewhere
  const std::string share = moved + "/share/pb4u", out = base + "/hanging", log = base + "/simulate.log";
  const int status = run_process({moved + "/bin/pb4u", "-v", "--threads", "1", "simulate", "--checkpoint",
                                  share + "/data/pretrained/pb4u.h5", "--scene", share + "/configs/scenes/hanging_cloth.yaml",
                                  "--frames", "2", "--out", out},
                                 log);
  const std::string text = test::read_file(log);
  ASSERT_EQ(status, 0) << text;
  EXPECT_NE(text.find("resources (scripts, configs, data): " + share), std::string::npos) << text;
  EXPECT_EQ(text.find(test::kSource + "/scripts"), std::string::npos) << text;
  EXPECT_TRUE(fs::exists(out + "/energies.csv")) << text;
  if (plot_python().empty()) GTEST_SKIP() << "no python3 with matplotlib on PATH: the preview is not drawn";
  EXPECT_TRUE(fs::exists(out + "/preview.png")) << text;
  remove_tree(base);  // not fs::remove_all: see remove_tree.h
}

}  // namespace
}  // namespace pb4u

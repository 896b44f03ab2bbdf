// The Blender add-on (scripts/blender/pb4u_addon), headless: a skinned cylinder and a tube
// pinned at its top (tests/eval/blender_addon_scene.py), one click of its operator, and the
// garment Blender then shows at every frame equals simulate's OBJ frames to 1e-6 m. Its three
// failures (no binary, a bad mesh, a failed run) come back as messages, and the USD layer it
// would load in a Blender with USD holds the same frames. Skipped without Blender.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "pb4u/eval/blender_cloth.h"
#include "pb4u/io/frame_sequence.h"
#include "pb4u/io/usd_cache.h"
#include "pb4u/sim/rollout_writer.h"
#include "pb4u/util/subprocess.h"
#include "test_util.h"

namespace pb4u {
namespace {

TEST(BlenderAddon, CachedFramesOnTheGarmentEqualSimulatesObjFrames) {
  const std::string blender = find_blender("blender");
  if (blender.empty()) GTEST_SKIP() << "Blender is not installed (scripts/install_deps.sh --blender)";
  const std::string dir = test::temp_dir("blender_addon");
  constexpr int kFrames = 10;
  const int status = run_process({blender, "-b", "--factory-startup", "--python",
                                  test::kSource + "/tests/eval/blender_addon_scene.py", "--", "--pb4u", PB4U_BINARY,
                                  "--out", dir, "--frames", std::to_string(kFrames), "--errors"},
                                 dir + "/blender.log");
  ASSERT_EQ(status, 0) << test::read_file(dir + "/blender.log");

  const std::string sim = dir + "/cache/simulate";
  double moved = 0;
  for (int t = 0; t <= kFrames; ++t) {
    const Eigen::MatrixXd shown = read_mesh_in_file_order(frame_file(dir, "blender", t, "obj")).V;
    const Eigen::MatrixXd simulated = read_mesh_in_file_order(frame_file(sim, "garment", t, "obj")).V;
    ASSERT_EQ(shown.rows(), simulated.rows());
    EXPECT_LE((shown - simulated).cwiseAbs().maxCoeff(), 1e-6) << "frame " << t;
    // The body simulate saw is the one Blender evaluated.
    const Eigen::MatrixXd body_in = read_mesh_in_file_order(frame_file(dir + "/cache", "body", t, "obj")).V;
    EXPECT_LE((read_mesh_in_file_order(frame_file(sim, "body", t, "obj")).V - body_in).cwiseAbs().maxCoeff(), 1e-6);
    if (t == kFrames)
      moved = (shown - read_mesh_in_file_order(frame_file(dir, "blender", 0, "obj")).V).rowwise().norm().maxCoeff();
  }
  EXPECT_GT(moved, 0.01) << "the cached garment does not move";

  // The USD layer the add-on gives a Blender that reads USD (the garment's space, z up): read
  // back in pb4u's axes, the same frames (the demo garment's transform is the identity).
  const UsdCache usd = read_usd_cache(dir + "/garment_blender.usda");
  ASSERT_EQ(usd.meshes.size(), 1u);
  EXPECT_EQ(usd.start_time_code, 1.0);  // the first Blender frame
  ASSERT_EQ(usd.meshes[0].frames.size(), size_t(kFrames + 1));
  for (int t = 0; t <= kFrames; ++t)
    EXPECT_LE((usd.meshes[0].frames[t] - read_mesh_in_file_order(frame_file(sim, "garment", t, "obj")).V)
                  .cwiseAbs()
                  .maxCoeff(),
              1e-6)
        << "USD frame " << t;

  const nlohmann::json result = nlohmann::json::parse(test::read_file(dir + "/result.json"));
  EXPECT_EQ(result.at("modifier"), "MESH_CACHE");
  const nlohmann::json& errors = result.at("errors");
  EXPECT_NE(errors.at("no_binary").get<std::string>().find("pb4u executable not found"), std::string::npos) << errors;
  EXPECT_NE(errors.at("bad_mesh").get<std::string>().find("1 loose vertices"), std::string::npos) << errors;
  EXPECT_NE(errors.at("failed_run").get<std::string>().find("pb4u simulate failed: pb4u: error: " + test::kSource +
                                                            "/README.md"),
            std::string::npos)
      << errors;
}

}  // namespace
}  // namespace pb4u

// An independent reader parses our USD cache: TinyUSDZ (npm package `tinyusdz`, WebAssembly,
// run by node; scripts/install_deps.sh --tinyusdz) finds the prims, point counts, time samples
// and stage metadata we wrote, and rejects a damaged copy. Skipped without node or tinyusdz.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>

#include "pb4u/io/usd_cache.h"
#include "pb4u/util/subprocess.h"
#include "test_util.h"

namespace pb4u {
namespace {

namespace fs = std::filesystem;

// The folder holding tinyusdz.js and tinyusdz.wasm: $PB4U_TINYUSDZ_DIR, else where
// install_deps.sh --tinyusdz puts it; empty when neither has it.
std::string tinyusdz_dir() {
  std::vector<std::string> candidates;
  if (const char* dir = std::getenv("PB4U_TINYUSDZ_DIR")) candidates.push_back(dir);
  if (const char* home = std::getenv("HOME")) candidates.push_back(std::string(home) + "/.cache/pb4u/node/node_modules/tinyusdz");
  for (const std::string& dir : candidates)
    if (fs::exists(dir + "/tinyusdz.js") && fs::exists(dir + "/tinyusdz.wasm")) return dir;
  return "";
}

nlohmann::json read_with_tinyusdz(const std::string& node, const std::string& module_dir, const std::string& usda) {
  const std::string out = usda + ".tinyusdz.json";
  const int status =
      run_process({node, test::kSource + "/tests/io/tinyusdz_read.mjs", module_dir, usda}, out);
  const std::string text = test::read_file(out);
  EXPECT_EQ(status, 0) << text;
  return nlohmann::json::parse(text.substr(text.find('{')));
}

TEST(UsdTinyUsdz, IndependentReaderFindsOurPrimsPointsAndTimeSamples) {
  const std::vector<std::string> node = find_all_on_path("node");
  const std::string module_dir = tinyusdz_dir();
  if (node.empty()) GTEST_SKIP() << "node is not installed (apt-get install nodejs)";
  if (module_dir.empty()) GTEST_SKIP() << "the npm package tinyusdz is not installed (scripts/install_deps.sh --tinyusdz)";

  const TriMesh g = test::grid_mesh(3, 0.6), b = test::grid_mesh(2, 2.0);
  UsdCache cache;
  cache.meshes.push_back({"Garment", g.F, {}, Eigen::Vector3d(0.85, 0.33, 0.22)});
  cache.meshes.push_back({"Body", b.F, {}, Eigen::Vector3d(0.7, 0.7, 0.75)});
  for (int t = 0; t < 5; ++t) {
    cache.meshes[0].frames.push_back(g.V + Eigen::MatrixXd::Constant(g.V.rows(), 3, 0.01 * t + 0.123456789));
    cache.meshes[1].frames.push_back(b.V * (1.0 + 0.1 * t));
  }
  const std::string dir = test::temp_dir("usd_tinyusdz");
  write_usd_cache(dir + "/scene.usda", cache);

  const nlohmann::json found = read_with_tinyusdz(node[0], module_dir, dir + "/scene.usda");
  ASSERT_TRUE(found.at("loaded").get<bool>()) << found.dump();
  const nlohmann::json& meta = found.at("metadata");
  EXPECT_EQ(meta.at("metersPerUnit"), "1");
  EXPECT_EQ(meta.at("upAxis"), "Y");
  EXPECT_EQ(meta.at("startTimeCode"), "0");
  EXPECT_EQ(meta.at("endTimeCode"), "4");
  EXPECT_EQ(meta.at("timeCodesPerSecond"), "30");
  EXPECT_EQ(meta.at("defaultPrim"), "pb4u");
  ASSERT_EQ(found.at("meshes").size(), 2u) << found.dump();
  for (size_t m = 0; m < 2; ++m) {
    const nlohmann::json& mesh = found.at("meshes")[m];
    const UsdMeshSequence& want = cache.meshes[m];
    EXPECT_EQ(mesh.at("path"), "/pb4u/" + want.name);
    EXPECT_EQ(mesh.at("points"), want.frames[0].rows());
    EXPECT_EQ(mesh.at("face_vertex_counts"), want.faces.rows());
    EXPECT_EQ(mesh.at("face_vertex_indices"), 3 * want.faces.rows());
    EXPECT_EQ(mesh.at("time_codes"), nlohmann::json({0, 1, 2, 3, 4})) << want.name;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(mesh.at("first_point")[k].get<double>(), want.frames[0](0, k), 1e-6);
  }

  // The reader is not lenient: a cache cut short is refused.
  const std::string text = test::read_file(dir + "/scene.usda");
  test::write_file(dir + "/cut.usda", text.substr(0, text.find("def Mesh \"Body\"") + 20));
  EXPECT_FALSE(read_with_tinyusdz(node[0], module_dir, dir + "/cut.usda").at("loaded").get<bool>());
}

}  // namespace
}  // namespace pb4u

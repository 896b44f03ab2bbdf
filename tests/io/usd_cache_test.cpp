// USD text caches: a written cache reads back with the OBJ frames' positions (float32, 1e-6 m)
// and the stage metadata a DCC needs; other tools' usda (z-up, centimetres, quads, materials,
// references) reads in metres and y up; bad files fail in one line naming the file.
#include <gtest/gtest.h>

#include <filesystem>

#include "pb4u/io/frame_sequence.h"
#include "pb4u/io/mesh_io.h"
#include "pb4u/io/usd_cache.h"
#include "pb4u/sim/rollout_writer.h"
#include "pb4u/util/error.h"
#include "test_util.h"

namespace pb4u {
namespace {

// A garment (a 3 x 3 grid) and a body (a 1 x 1 grid below it) over 4 frames of random motion.
UsdCache two_mesh_cache() {
  const TriMesh g = test::grid_mesh(3, 0.6), b = test::grid_mesh(1, 2.0);
  UsdCache cache;
  cache.meshes.push_back({"Garment", g.F, {}, Eigen::Vector3d(0.85, 0.33, 0.22)});
  cache.meshes.push_back({"Body", b.F, {}, Eigen::Vector3d(0.7, 0.7, 0.75)});
  for (int t = 0; t < 4; ++t) {
    cache.meshes[0].frames.push_back(g.V + 0.05 * Eigen::MatrixXd::Random(g.V.rows(), 3));
    Eigen::MatrixXd x = b.V;
    x.col(1).array() -= 0.3 + 0.01 * t;
    cache.meshes[1].frames.push_back(x);
  }
  return cache;
}

TEST(UsdCache, ReadsBackTheObjFramesToAMicrometre) {
  const std::string dir = test::temp_dir("usd_roundtrip");
  const UsdCache cache = two_mesh_cache();
  write_usd_cache(dir + "/scene.usda", cache);
  for (size_t t = 0; t < 4; ++t) write_mesh(frame_file(dir, "garment", int(t), "obj"), {cache.meshes[0].frames[t], cache.meshes[0].faces});

  const UsdCache back = read_usd_cache(dir + "/scene.usda");
  EXPECT_EQ(back.fps, 30.0);
  EXPECT_EQ(back.start_time_code, 0.0);
  ASSERT_EQ(back.meshes.size(), 2u);
  for (size_t m = 0; m < 2; ++m) {
    EXPECT_EQ(back.meshes[m].name, cache.meshes[m].name);
    EXPECT_EQ(back.meshes[m].faces, cache.meshes[m].faces);
    ASSERT_EQ(back.meshes[m].frames.size(), 4u);
  }
  for (size_t t = 0; t < 4; ++t) {
    const TriMesh obj = read_mesh_in_file_order(frame_file(dir, "garment", int(t), "obj"));
    EXPECT_LE((back.meshes[0].frames[t] - obj.V).cwiseAbs().maxCoeff(), 1e-6) << "frame " << t;
    EXPECT_LE((back.meshes[1].frames[t] - cache.meshes[1].frames[t]).cwiseAbs().maxCoeff(), 1e-6) << "frame " << t;
  }
  // As a frame sequence (what `score` reads): the prim named like the group, with its faces.
  const FrameSequence body = read_frame_sequence(dir + "/scene.usda", "body");
  EXPECT_EQ(body.frames.size(), 4u);
  EXPECT_EQ(body.faces, cache.meshes[1].faces);
  EXPECT_THROW(read_frame_sequence(dir + "/scene.usda", "hat"), Error);
}

TEST(UsdCache, StageMetadataSaysMetresYUpAndTheFrameRange) {
  const std::string dir = test::temp_dir("usd_meta");
  UsdCache cache = two_mesh_cache();
  cache.fps = 25;
  cache.start_time_code = 1;
  write_usd_cache(dir + "/a.usda", cache);
  const std::string text = test::read_file(dir + "/a.usda");
  EXPECT_EQ(text.rfind("#usda 1.0\n", 0), 0u);
  for (const char* line : {"metersPerUnit = 1\n", "upAxis = \"Y\"\n", "startTimeCode = 1\n", "endTimeCode = 4\n",
                           "timeCodesPerSecond = 25\n", "framesPerSecond = 25\n", "defaultPrim = \"pb4u\"\n",
                           "def Mesh \"Garment\"", "def Mesh \"Body\"", "uniform token subdivisionScheme = \"none\"",
                           "color3f[] primvars:displayColor = [(0.850000024, 0.330000013, 0.219999999)]",
                           "point3f[] points.timeSamples = {\n            1: [", "\n            4: ["})
    EXPECT_NE(text.find(line), std::string::npos) << line;
  const UsdCache back = read_usd_cache(dir + "/a.usda");
  EXPECT_EQ(back.fps, 25.0);
  EXPECT_EQ(back.start_time_code, 1.0);
}

// What Blender's or Houdini's exports hold beyond ours: z up in centimetres, a quad, transforms,
// a material with connections, list edits, a reference, comments.
TEST(UsdCache, ReadsOtherToolsLayersInMetresYUp) {
  const std::string dir = test::temp_dir("usd_foreign");
  test::write_file(dir + "/z.usda", R"(#usda 1.0
(
    "exported by hand"  # a doc string
    metersPerUnit = 0.01
    upAxis = "Z"
    customLayerData = {
        string creator = "test"
        dictionary nested = { int a = 1 }
    }
)

def Xform "root" (
    prepend references = @./other.usda@</Other>
)
{
    double3 xformOp:translate = (0, 0, 0)
    uniform token[] xformOpOrder = ["xformOp:translate"]
    def Mesh "Cloth" (
        prepend apiSchemas = ["MaterialBindingAPI"]
    )
    {
        int[] faceVertexCounts = [4]
        int[] faceVertexIndices = [0, 1, 2, 3]
        point3f[] points = [(0, 0, 0), (100, 0, 0), (100, 100, 0), (0, 100, -1.5e2)]
        texCoord2f[] primvars:st = [(0, 0), (1, 0), (1, 1), (0, 1)] (
            interpolation = "faceVarying"
        )
        rel material:binding = </root/Looks/M>
    }
    def Scope "Looks"
    {
        def Material "M"
        {
            token outputs:surface.connect = </root/Looks/M/S.outputs:surface>
        }
    }
}
)");
  const UsdCache cache = read_usd_cache(dir + "/z.usda");
  EXPECT_EQ(cache.fps, 24.0);  // USD's default timeCodesPerSecond
  ASSERT_EQ(cache.meshes.size(), 1u);
  EXPECT_EQ(cache.meshes[0].name, "Cloth");
  ASSERT_EQ(cache.meshes[0].frames.size(), 1u);
  Eigen::MatrixXd want(4, 3);
  want << 0, 0, 0, 1, 0, 0, 1, 0, -1, 0, -1.5, -1;  // (x, y, z) cm z-up -> (x, z, -y) m y-up
  EXPECT_TRUE(cache.meshes[0].frames[0].isApprox(want, 1e-12)) << cache.meshes[0].frames[0];
  Eigen::MatrixXi fan(2, 3);
  fan << 0, 1, 2, 0, 2, 3;
  EXPECT_EQ(cache.meshes[0].faces, fan);
  // The only Mesh of a file is the garment, whatever its name.
  EXPECT_EQ(read_frame_sequence(dir + "/z.usda", "garment").frames.size(), 1u);

  // float32 points (point3f, float3) read as the floats they are; point3d keeps its digits.
  for (const std::string type : {"point3f", "float3", "point3d"}) {
    test::write_file(dir + "/p.usda", "#usda 1.0\ndef Mesh \"M\" {\n int[] faceVertexCounts = [3]\n"
                                      " int[] faceVertexIndices = [0, 1, 2]\n " + type +
                                          "[] points = [(0.1, 0, 0), (1, 0, 0), (0, 1, 0)]\n}\n");
    const double x = read_usd_cache(dir + "/p.usda").meshes.at(0).frames.at(0)(0, 0);
    EXPECT_EQ(x, type == "point3d" ? 0.1 : double(0.1f)) << type;
  }
}

// Each bad file fails with one line that starts with its path (and names the line).
TEST(UsdCache, BadFilesFailNamingTheFile) {
  const std::string dir = test::temp_dir("usd_bad");
  write_usd_cache(dir + "/good.usda", two_mesh_cache());
  const std::string good = test::read_file(dir + "/good.usda");
  // The first `from` after `after`.
  auto replaced = [&](const std::string& from, const std::string& to, const std::string& after = "#usda") {
    std::string s = good;
    s.replace(s.find(from, s.find(after)), from.size(), to);
    return s;
  };
  const std::vector<std::pair<std::string, std::string>> cases{
      {"missing.usda", ""},
      {"not_usd.usda", "v 0 0 0\n"},
      {"binary.usda", std::string("PXR-USDC") + std::string(80, '\0')},
      {"truncated.usda", good.substr(0, good.size() / 2)},
      {"bad_index.usda", replaced("int[] faceVertexIndices = [0", "int[] faceVertexIndices = [99")},
      {"bad_count.usda", replaced("int[] faceVertexCounts = [3", "int[] faceVertexCounts = [2")},
      {"short_sample.usda", replaced("            1: [(", "            1: [(0, 0, 0), (", "point3f[] points")},
      {"bad_number.usda", replaced("            2: [(", "            2: [(x, ")},
      {"bad_units.usda", replaced("metersPerUnit = 1", "metersPerUnit = 0")},
      {"unclosed.usda", replaced("def Mesh \"Body\"", "def Mesh \"Body")},
  };
  for (const auto& [name, text] : cases) {
    const std::string path = dir + "/" + name;
    if (!text.empty()) test::write_file(path, text);
    try {
      read_usd_cache(path);
      ADD_FAILURE() << name << " was read";
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(path + ": ", 0), 0u) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
  // Inconsistent input is refused before anything is written.
  UsdCache uneven = two_mesh_cache();
  uneven.meshes[1].frames.pop_back();
  EXPECT_THROW(write_usd_cache(dir + "/uneven.usda", uneven), Error);
  UsdCache bad_name = two_mesh_cache();
  bad_name.meshes[0].name = "my garment";
  EXPECT_THROW(write_usd_cache(dir + "/bad_name.usda", bad_name), Error);
  EXPECT_FALSE(std::filesystem::exists(dir + "/uneven.usda"));
}

}  // namespace
}  // namespace pb4u

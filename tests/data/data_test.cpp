// LBS-initialised frames, the HDF5 dataset (round trip, corrupt files) and `pb4u generate`.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "pb4u/body/humanoid.h"
#include "pb4u/data/generate.h"
#include "pb4u/data/lbs_frame.h"
#include "pb4u/garment/garment_template.h"
#include "pb4u/mesh/edges.h"
#include "pb4u/spatial/segments_through_surface.h"
#include "pb4u/spatial/signed_distance_to_surface.h"
#include "pb4u/util/error.h"
#include "../body/strip_gltf.h"
#include "test_util.h"

using namespace pb4u;

namespace {

// A small config: tiny meshes and motions so the whole pipeline runs in seconds.
GenerateConfig tiny_config() {
  GenerateConfig c;
  c.levels.triangles = {200, 330, 450};
  c.mannequin.vertices = 400;
  c.mannequin.cell_size = 0.015;
  c.garments.cell_size = 0.015;
  c.templates = {"tshirt", "skirt"};
  c.procedural.kinds = {"walk", "spin"};
  c.procedural.per_kind = 2;
  c.procedural.frames = 12;
  return c;
}

const Dataset& tiny_dataset() {
  static Dataset d = generate_dataset(tiny_config());
  return d;
}

// A closed unit cube [0,1]^3 with outward faces.
TriMesh cube() {
  TriMesh m;
  m.V.resize(8, 3);
  for (int i = 0; i < 8; ++i) m.V.row(i) << (i & 1), (i >> 1) & 1, (i >> 2) & 1;
  m.F.resize(12, 3);
  m.F << 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6,
      1, 3, 5, 3, 7, 5;
  return m;
}

}  // namespace

TEST(LbsFrame, PushOutMovesPenetratingPointsToTheGap) {
  const TriMesh body = cube();
  Eigen::MatrixXd X(3, 3);
  X << 0.5, 0.5, 0.95,  // inside, nearest face z = 1
      0.5, 0.5, 1.5,    // outside, far
      0.5, 0.02, 0.5;   // inside, nearest face y = 0 (by centroid)
  const int moved = push_out_of_body(X, body.V, body.F, 0.01);
  EXPECT_EQ(moved, 2);
  EXPECT_NEAR(X(0, 2), 1.01, 1e-12);
  EXPECT_NEAR(X(1, 2), 1.5, 1e-12);
  EXPECT_NEAR(X(2, 1), -0.01, 1e-12);
}

TEST(LbsFrame, BindPoseFramesAreRestAndMotionGivesVelocity) {
  const Dataset& d = tiny_dataset();
  const BodyRecord& rec = d.bodies[0];
  const Garment& g = rec.garments[0].levels[0];
  Motion still;
  still.frames.assign(3, rec.body.bind);
  const LbsFrame f = lbs_frame(rec.body, g, still, 1, 0.006);
  EXPECT_LT((f.body - rec.body.mesh.V).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((f.garment - f.garment_prev).cwiseAbs().maxCoeff(), 1e-12);  // zero velocity
  // The template already clears the body: the pre-solve only corrects the coarse body's
  // chords, moving few vertices by less than 1.5 gaps.
  const Eigen::VectorXd moved = (f.garment - g.mesh.V).rowwise().norm();
  EXPECT_LT(moved.maxCoeff(), 1.5 * 0.006);
  EXPECT_LT((moved.array() > 1e-9).count(), g.mesh.num_vertices() / 5);
  const MotionRecord& walk = d.motions[0];
  const LbsFrame w = lbs_frame(rec.body, g, walk.motion, 5, 0.006);
  EXPECT_GT((w.garment - w.garment_prev).rowwise().norm().maxCoeff(), 1e-3);
  EXPECT_GT((w.body_next - w.body).rowwise().norm().maxCoeff(), 1e-3);
  EXPECT_TRUE(w.garment.allFinite() && w.body_prev.allFinite());
}

// Every level of every garment is free of its body at the bind pose, edges included
// (GarmentTemplateConfig::rest_clearance): the tiny dataset's coarsest t-shirt had 36 of its 321
// edges through the mannequin's arms and shoulders before its rest mesh was cleared.
TEST(Generate, EveryGarmentLevelIsFreeOfItsBodyAtTheBindPose) {
  const Dataset& d = tiny_dataset();
  const double clearance = GarmentTemplateConfig{}.rest_clearance;
  ASSERT_GT(clearance, 0.0);
  for (const BodyRecord& rec : d.bodies)
    for (const GarmentLevels& gl : rec.garments)
      for (size_t k = 0; k < gl.levels.size(); ++k) {
        const TriMesh& m = gl.levels[k].mesh;
        const std::string where = rec.body.name + "/" + gl.name + " level " + std::to_string(k + 1);
        EXPECT_TRUE(segments_through_surface(m.V, unique_edges(m.F), rec.body.mesh.V, rec.body.mesh.F).empty()) << where;
        EXPECT_GE(signed_distance_to_surface(m.V, rec.body.mesh.V, rec.body.mesh.F).minCoeff(), clearance * (1 - 1e-6))
            << where;
      }
}

TEST(Dataset, RoundTripKeepsEverything) {
  const Dataset& d = tiny_dataset();
  const std::string path = test::temp_dir("ds") + "/d.h5";
  write_dataset(path, d);
  const Dataset r = read_dataset(path);
  EXPECT_EQ(r.level_triangles, d.level_triangles);
  ASSERT_EQ(r.bodies.size(), d.bodies.size());
  const Body &a = d.bodies[0].body, &b = r.bodies[0].body;
  EXPECT_EQ(a.mesh.F, b.mesh.F);
  EXPECT_LT((a.mesh.V - b.mesh.V).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((a.weights - b.weights).cwiseAbs().maxCoeff(), 1e-6);  // stored as float32
  EXPECT_EQ(a.skeleton.names, b.skeleton.names);
  EXPECT_EQ(a.skeleton.parents, b.skeleton.parents);
  ASSERT_EQ(r.bodies[0].garments.size(), 2u);
  EXPECT_EQ(r.bodies[0].garments[1].levels.size(), 3u);
  // Groups come back in name order: skirt before tshirt.
  EXPECT_EQ(r.bodies[0].garments[0].name, "skirt");
  EXPECT_EQ(r.bodies[0].garments[0].levels[2].mesh.F, d.bodies[0].garments[1].levels[2].mesh.F);
  ASSERT_EQ(r.motions.size(), d.motions.size());
  int tests = 0;
  for (size_t i = 0; i < r.motions.size(); ++i) {
    const MotionRecord* m = nullptr;
    for (const auto& x : d.motions)
      if (x.name == r.motions[i].name) m = &x;
    ASSERT_NE(m, nullptr);
    EXPECT_EQ(r.motions[i].split, m->split);
    tests += m->split == "test";
    ASSERT_EQ(r.motions[i].motion.num_frames(), m->motion.num_frames());
    // Posing through the file gives the same body as posing from memory.
    const Eigen::MatrixXd p0 = pose_body(a, m->motion.frames[7]);
    const Eigen::MatrixXd p1 = pose_body(b, r.motions[i].motion.frames[7]);
    EXPECT_LT((p0 - p1).cwiseAbs().maxCoeff(), 1e-5);
  }
  EXPECT_EQ(tests, 1);  // 25% of 4 motions
}

TEST(Dataset, BadFilesGiveOneLineErrorsNamingTheFile) {
  const std::string dir = test::temp_dir("bad");
  auto expect_error = [](const std::string& path) {
    try {
      read_dataset(path);
      ADD_FAILURE() << "no error for " << path;
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(path, 0), 0u) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  };
  expect_error(dir + "/missing.h5");
  test::write_file(dir + "/text.h5", "not hdf5 at all");
  expect_error(dir + "/text.h5");
  const std::string good = dir + "/good.h5";
  write_dataset(good, tiny_dataset());
  const std::string bytes = test::read_file(good);
  test::write_file(dir + "/truncated.h5", bytes.substr(0, bytes.size() / 2));
  expect_error(dir + "/truncated.h5");
  EXPECT_FALSE(std::filesystem::exists(good + ".tmp"));
}

TEST(GenerateCommand, WritesDatasetAndConfigAndRefusesToOverwrite) {
  const std::string dir = test::temp_dir("gen");
  test::write_file(dir + "/c.yaml",
                   "file: t.h5\nlevels: {triangles: [150, 250]}\n"
                   "mannequin: {vertices: 300, cell_size: 0.02}\n"
                   "garments: {cell_size: 0.02}\ntemplates: [tank_top]\n"
                   "procedural: {kinds: [jump], per_kind: 2, frames: 5}\n");
  const std::string out = dir + "/out";
  auto r = test::run_pb4u("-q generate --config " + dir + "/c.yaml --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(out + "/t.h5"));
  EXPECT_TRUE(std::filesystem::exists(out + "/config.yaml"));
  r = test::run_pb4u("-q generate --config " + dir + "/c.yaml --out " + out);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--force"), std::string::npos) << r.err;
  r = test::run_pb4u("inspect " + out + "/t.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("garment tank_top"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("motions: 2 (1 train, 1 test)"), std::string::npos) << r.out;
  r = test::run_pb4u("inspect " + std::string(PB4U_MOCAP_DATA) + "/cmu_131_02.bvh");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("frames: 1248"), std::string::npos) << r.out;
  // A bad key is one line naming the file and the key.
  test::write_file(dir + "/bad.yaml", "levels: {triangles: [300, 200]}\n");
  r = test::run_pb4u("generate --config " + dir + "/bad.yaml --out " + out + "2");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("levels.triangles[1]"), std::string::npos) << r.err;
}

TEST(Generate, SkinnedMeshBodiesBringTheirAnimations) {
  const std::string path = test::temp_dir("skinbody") + "/strip.gltf";
  test::write_file(path, test::strip_gltf());
  GenerateConfig c;
  c.levels.triangles = {100};
  BodySpec spec;
  spec.name = "strip";
  spec.mesh = path;
  c.bodies = {spec};
  c.procedural.per_kind = 0;
  validate_generate_config(c, "test");
  const Dataset d = generate_dataset(c);
  ASSERT_EQ(d.bodies.size(), 1u);
  EXPECT_TRUE(d.bodies[0].garments.empty());  // templates need a mannequin
  ASSERT_EQ(d.motions.size(), 1u);
  EXPECT_EQ(d.motions[0].name, "strip_bend");
  EXPECT_EQ(d.motions[0].motion.num_frames(), 31);
  EXPECT_EQ(d.motions[0].split, "train");
}

TEST(Generate, BvhMotionsNeedABodyBuiltFromTheirSkeleton) {
  GenerateConfig c = tiny_config();
  c.templates.clear();
  c.procedural.per_kind = 0;
  const std::string bvh = std::string(PB4U_MOCAP_DATA) + "/cmu_131_01.bvh";
  c.bodies = {BodySpec{"cmu", bvh, ""}};
  c.bvh.body = "cmu";
  c.bvh.files = {bvh};
  c.bvh.max_frames = 20;
  Dataset d = generate_dataset(c);
  ASSERT_EQ(d.motions.size(), 1u);
  EXPECT_EQ(d.motions[0].motion.num_frames(), 20);
  EXPECT_DOUBLE_EQ(d.motions[0].motion.fps, 30.0);
  // The same file on the built-in mannequin: a clear error, not a silent retarget.
  c.bodies = {BodySpec{"cmu", "builtin", ""}};
  try {
    generate_dataset(c);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("joints differ"), std::string::npos) << e.what();
  }
}

TEST(Generate, ResultDoesNotDependOnTheWorkerCount) {
  const Dataset one = generate_dataset(tiny_config(), "", 1);
  const Dataset& two = tiny_dataset();  // built with one worker per core
  ASSERT_EQ(one.bodies[0].garments.size(), two.bodies[0].garments.size());
  for (size_t g = 0; g < one.bodies[0].garments.size(); ++g) {
    const TriMesh& a = one.bodies[0].garments[g].levels[0].mesh;
    const TriMesh& b = two.bodies[0].garments[g].levels[0].mesh;
    EXPECT_EQ(a.F, b.F);
    EXPECT_EQ(a.V, b.V);
  }
  for (size_t m = 0; m < one.motions.size(); ++m) EXPECT_EQ(one.motions[m].split, two.motions[m].split);
}

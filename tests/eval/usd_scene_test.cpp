// A scene whose body is a mesh sequence (body.mesh_sequence, what the Blender add-on exports)
// simulated by the real binary: its scene.usda holds the OBJ frames of garment and body to
// 1e-6 m, pins on the body ride with it, and `score` reads the USD cache to the same figures
// as the PC2 caches (the same float32 positions) and the OBJ frames; bad input fails in one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "pb4u/io/frame_sequence.h"
#include "pb4u/io/mesh_io.h"
#include "pb4u/io/point_cache.h"
#include "pb4u/io/usd_cache.h"
#include "pb4u/sim/rollout_writer.h"
#include "eval/eval_test_util.h"
#include "test_util.h"

namespace pb4u {
namespace {

using test::read_csv;

// A closed cylinder along y (outward faces): `segments` around, `rings` levels, capped.
TriMesh closed_cylinder(double radius, double y0, double y1, int segments, int rings) {
  TriMesh m;
  m.V.resize(segments * rings + 2, 3);
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double a = 2 * M_PI * s / segments;
      m.V.row(r * segments + s) << radius * std::cos(a), y0 + (y1 - y0) * r / (rings - 1), radius * std::sin(a);
    }
  const int bottom = segments * rings, top = bottom + 1;
  m.V.row(bottom) << 0, y0, 0;
  m.V.row(top) << 0, y1, 0;
  std::vector<Eigen::Vector3i> f;
  for (int r = 0; r + 1 < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const int a = r * segments + s, b = (r + 1) * segments + s, c = (r + 1) * segments + (s + 1) % segments,
                d = r * segments + (s + 1) % segments;
      f.emplace_back(a, b, c);
      f.emplace_back(a, c, d);
    }
  for (int s = 0; s < segments; ++s) {
    f.emplace_back(bottom, s, (s + 1) % segments);
    f.emplace_back(top, (rings - 1) * segments + (s + 1) % segments, (rings - 1) * segments + s);
  }
  m.F.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (size_t i = 0; i < f.size(); ++i) m.F.row(static_cast<Eigen::Index>(i)) = f[i].transpose();
  return m;
}

constexpr int kFrames = 4;
constexpr double kBodyStep = 0.01;  // m per frame along x

// A 0.3 m square cloth pinned at its top row in front of a cylinder that slides along x; the
// pins ride on the body. Simulated with the shipped model. Returns the scene's folder.
std::string simulated_on_body_sequence(const std::string& tag) {
  const std::string dir = test::temp_dir(tag);
  TriMesh body = closed_cylinder(0.1, 0.5, 1.3, 12, 9);
  body.V.col(2).array() -= 0.15;
  for (int t = 0; t <= kFrames; ++t) {
    TriMesh moved = body;
    moved.V.col(0).array() += kBodyStep * t;
    write_mesh(frame_file(dir, "body_in", t, "obj"), moved);
  }
  test::write_file(dir + "/scene.yaml",
                   "frames: " + std::to_string(kFrames) +
                       "\neffects: [gravity, collision, friction, pins]\n"
                       "garment: {source: square, size: 0.3, resolution: 7, height: 1.2}\n"
                       "body: {mesh_sequence: body_in_%04d.obj}\n"  // beside the scene file
                       "pins: {top_band: 0.001, on_body: true}\n"
                       "outputs: {plot: false, preview: false}\n");
  auto run = test::run_pb4u("-q simulate --checkpoint " + test::kSource + "/data/pretrained/pb4u.h5 --scene " + dir +
                            "/scene.yaml --out " + dir + "/sim");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  return dir;
}

double max_difference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  EXPECT_EQ(a.rows(), b.rows());
  return a.rows() == b.rows() ? (a - b).cwiseAbs().maxCoeff() : 1e9;
}

TEST(UsdScene, SceneUsdaHoldsTheObjFramesOfGarmentAndBody) {
  const std::string dir = simulated_on_body_sequence("usd_scene"), sim = dir + "/sim";
  const UsdCache usd = read_usd_cache(sim + "/scene.usda");
  EXPECT_EQ(usd.fps, 30.0);
  ASSERT_EQ(usd.meshes.size(), 2u);
  ASSERT_EQ(usd.meshes[0].name, "Garment");
  ASSERT_EQ(usd.meshes[1].name, "Body");
  ASSERT_EQ(usd.meshes[0].frames.size(), size_t(kFrames + 1));
  ASSERT_EQ(usd.meshes[1].frames.size(), size_t(kFrames + 1));
  for (int t = 0; t <= kFrames; ++t) {
    const TriMesh g = read_mesh_in_file_order(frame_file(sim, "garment", t, "obj"));
    const TriMesh b = read_mesh_in_file_order(frame_file(sim, "body", t, "obj"));
    const TriMesh in = read_mesh_in_file_order(frame_file(dir, "body_in", t, "obj"));
    EXPECT_LE(max_difference(usd.meshes[0].frames[t], g.V), 1e-6) << "garment frame " << t;
    EXPECT_LE(max_difference(usd.meshes[1].frames[t], b.V), 1e-6) << "body frame " << t;
    EXPECT_LE(max_difference(b.V, in.V), 1e-6) << "the body is the given sequence, frame " << t;
    if (t == 0) {
      EXPECT_EQ(usd.meshes[0].faces, g.F);
      EXPECT_EQ(usd.meshes[1].faces, in.F);
    }
  }
  // The top row rode on the body: it moved with the cylinder, kBodyStep per frame.
  const Eigen::MatrixXd& x0 = usd.meshes[0].frames[0];
  const Eigen::MatrixXd& xT = usd.meshes[0].frames[kFrames];
  int top_row = 0;
  for (Eigen::Index i = 0; i < x0.rows(); ++i) {
    if (x0(i, 1) < x0.col(1).maxCoeff() - 1e-6) continue;
    ++top_row;
    EXPECT_NEAR(xT(i, 0) - x0(i, 0), kBodyStep * kFrames, 1e-6) << "vertex " << i;
    EXPECT_NEAR(xT(i, 1), x0(i, 1), 1e-6) << "vertex " << i;
  }
  EXPECT_EQ(top_row, 7);
}

TEST(UsdScene, ScoreReadsTheUsdCacheLikeThePointCachesAndTheObjFrames) {
  const std::string dir = simulated_on_body_sequence("usd_score"), sim = dir + "/sim";
  auto usd = test::run_pb4u("-q score --frames " + sim + "/scene.usda --garment " + sim + "/garment_rest.obj --format csv");
  ASSERT_EQ(usd.exit_code, 0) << usd.err;
  auto pc2 = test::run_pb4u("-q score --frames " + sim + "/garment.pc2 --garment " + sim + "/garment_rest.obj --body-frames " +
                            sim + "/body.pc2 --body " + sim + "/body_0000.obj --format csv");
  ASSERT_EQ(pc2.exit_code, 0) << pc2.err;
  auto obj = test::run_pb4u("-q score --frames '" + sim + "/garment_%04d.obj' --garment " + sim +
                            "/garment_rest.obj --body-frames '" + sim + "/body_%04d.obj' --format csv");
  ASSERT_EQ(obj.exit_code, 0) << obj.err;
  // The body came from the USD file itself: collision and penetration columns are there.
  EXPECT_NE(usd.out.find("collision"), std::string::npos) << usd.out;
  EXPECT_NE(usd.out.find("penetrating_fraction"), std::string::npos) << usd.out;
  // USD and PC2 hold the same float32 positions: the same figures to the digit.
  EXPECT_EQ(usd.out, pc2.out);
  // OBJ keeps 9 digits: the position terms agree to float32 rounding (velocity terms, which
  // difference positions 1/30 s apart, are left out as in the PC2 test of score_test.cpp).
  test::write_file(dir + "/usd.csv", usd.out);
  test::write_file(dir + "/obj.csv", obj.out);
  const auto u = read_csv(dir + "/usd.csv"), o = read_csv(dir + "/obj.csv");
  ASSERT_EQ(u.size(), size_t(kFrames + 2));
  ASSERT_EQ(u[0], o[0]);
  for (size_t c = 1; c < u[0].size(); ++c) {
    if (u[0][c] != "stretch" && u[0][c] != "bending" && u[0][c] != "gravity" && u[0][c] != "collision") continue;
    for (size_t r = 2; r < u.size(); ++r) {
      const double a = std::stod(o[r][c]), b = std::stod(u[r][c]);
      EXPECT_NEAR(b, a, 1e-4 * std::abs(a) + 1e-9) << u[0][c] << " row " << r;
    }
  }
}

// garment.keep_vertex_order: vertex i of the outputs is vertex i of the file (what a DCC's
// point cache needs); the default import orders them by first use in the faces.
TEST(UsdScene, KeepVertexOrderKeepsTheFilesVertices) {
  const std::string dir = test::temp_dir("keep_order");
  TriMesh cloth = test::grid_mesh(3, 0.3);
  cloth.V.col(1).array() += 1.0;
  cloth.F = cloth.F.colwise().reverse().eval();  // the last vertices are used first
  write_mesh(dir + "/cloth.obj", cloth);
  const std::string scene = "frames: 1\neffects: [gravity]\noutputs: {plot: false, preview: false}\n"
                            "garment: {source: file, file: " + dir + "/cloth.obj";
  test::write_file(dir + "/kept.yaml", scene + ", keep_vertex_order: true}\n");
  test::write_file(dir + "/default.yaml", scene + "}\n");
  for (const char* name : {"kept", "default"}) {
    auto r = test::run_pb4u("-q simulate --checkpoint " + test::kSource + "/data/pretrained/pb4u.h5 --scene " + dir +
                            "/" + name + ".yaml --out " + dir + "/" + name);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  const TriMesh file = read_mesh_in_file_order(dir + "/cloth.obj");
  const TriMesh kept = read_mesh_in_file_order(dir + "/kept/garment_rest.obj");
  const TriMesh imported = read_mesh_in_file_order(dir + "/default/garment_rest.obj");
  EXPECT_EQ(kept.V, file.V);
  EXPECT_EQ(kept.F, file.F);
  ASSERT_EQ(imported.V.rows(), file.V.rows());
  EXPECT_NE(imported.V, file.V);
  // A remeshed garment has new vertices: asking for both is an error naming the key.
  test::write_file(dir + "/both.yaml", scene + ", keep_vertex_order: true, triangles: 50}\n");
  auto r = test::run_pb4u("-q simulate --checkpoint " + test::kSource + "/data/pretrained/pb4u.h5 --scene " + dir +
                          "/both.yaml --out " + dir + "/both");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("garment.keep_vertex_order"), std::string::npos) << r.err;
}

TEST(UsdScene, BadUsdAndBodySequencesFailInOneLineNamingTheFile) {
  const std::string dir = test::temp_dir("usd_scene_bad");
  test::write_file(dir + "/bad.usda", "#usda 1.0\ndef Mesh \"Garment\" {\n  point3f[] points = [(0, 0)]\n}\n");
  auto r = test::run_pb4u("-q score --frames " + dir + "/bad.usda --garment " + dir + "/none.obj");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err.rfind("pb4u: error: " + dir + "/bad.usda: ", 0), 0u) << r.err;

  // A body sequence without faces (a point cache), and a body given twice.
  const std::string scene = "frames: 2\neffects: [gravity, collision]\ngarment: {source: square, resolution: 4}\n";
  test::write_file(dir + "/pc2.yaml", scene + "body: {mesh_sequence: " + dir + "/body.pc2}\n");
  write_pc2(dir + "/body.pc2", {closed_cylinder(0.1, 0.5, 1.3, 8, 3).V});
  r = test::run_pb4u("-q simulate --checkpoint " + test::kSource + "/data/pretrained/pb4u.h5 --scene " + dir +
                     "/pc2.yaml --out " + dir + "/out");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(dir + "/body.pc2: body.mesh_sequence: a point cache has no faces"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  test::write_file(dir + "/both.yaml", scene + "body: {mesh_sequence: x.usda, dataset: y.h5}\n");
  r = test::run_pb4u("-q simulate --checkpoint " + test::kSource + "/data/pretrained/pb4u.h5 --scene " + dir +
                     "/both.yaml --out " + dir + "/out");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("body.mesh_sequence"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace pb4u

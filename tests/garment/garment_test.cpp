// Garment templates (no penetration, same shape at every level, triangle counts, edge-length
// scaling), imported triangle soups, weight transfer, clipping.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "mesh_distance.h"
#include "pb4u/body/humanoid.h"
#include "pb4u/body/procedural_motion.h"
#include "pb4u/data/lbs_frame.h"
#include "pb4u/garment/clip_mesh.h"
#include "pb4u/garment/garment_template.h"
#include "pb4u/garment/import_garment.h"
#include "pb4u/garment/skin_weight_transfer.h"
#include "pb4u/mesh/geometry.h"
#include "pb4u/mesh/topology.h"
#include "pb4u/physics/cloth_geometry.h"
#include "pb4u/physics/stretch_energy.h"
#include "pb4u/util/eigen_tensor.h"
#include "pb4u/util/error.h"
#include "test_util.h"

using namespace pb4u;

namespace {

MannequinConfig mannequin_config() {
  MannequinConfig c;
  c.vertices = 2500;
  c.cell_size = 0.012;
  return c;
}

GarmentTemplateConfig template_config() {
  GarmentTemplateConfig c;
  c.cell_size = 0.012;
  return c;
}

// One mannequin and the template surfaces, shared by the tests (built once).
struct Fixture {
  Body body;
  std::map<std::string, TriMesh> surfaces;
  Fixture() {
    body = build_mannequin("builtin", builtin_skeleton(), mannequin_config());
    for (const auto& name : garment_template_names())
      surfaces[name] = garment_template_surface(name, body, mannequin_config(), template_config());
  }
};
const Fixture& fixture() {
  static Fixture f;
  return f;
}

// The CPU scale's first three levels.
const std::vector<int> kLevels = {2000, 3300, 4500};

}  // namespace

TEST(ClipMesh, CutsAlongTheLevelSetAndKeepsTheArea) {
  const TriMesh grid = test::grid_mesh(8, 1.0);  // xz plane, [0, 1]^2
  Eigen::VectorXd g = 0.37 - grid.V.col(0).array();  // keep x <= 0.37
  const TriMesh half = clip_mesh(grid, g);
  EXPECT_NEAR(face_areas(half.V, half.F).sum(), 0.37, 1e-9);
  EXPECT_LE(half.V.col(0).maxCoeff(), 0.37 + 1e-12);
  EXPECT_EQ(boundary_loops(half.F).size(), 1u);
  EXPECT_TRUE(check_manifold(half.F, half.num_vertices()).oriented());
}

TEST(GarmentTemplates, DoNotPenetrateTheMannequinAtRest) {
  const Fixture& f = fixture();
  for (const auto& [name, surface] : f.surfaces) {
    const Garment g = make_garment(name, surface, f.body, kLevels[0]);
    double worst = 1e9;
    for (int i = 0; i < g.mesh.num_vertices(); ++i)
      worst = std::min(worst, test::signed_distance(g.mesh.V.row(i), f.body.mesh));
    EXPECT_GT(worst, 0.0) << name;
    EXPECT_LT(worst, 0.02) << name << " should hug the body somewhere";
    EXPECT_LT((g.weights.rowwise().sum().array() - 1).abs().maxCoeff(), 1e-9);
  }
}

TEST(GarmentTemplates, LevelsHitTheirCountsKeepTheShapeAndScaleEdges) {
  const Fixture& f = fixture();
  for (const auto& [name, surface] : f.surfaces) {
    std::vector<TriMesh> levels;
    for (int t : kLevels) {
      levels.push_back(make_garment(name, surface, f.body, t).mesh);
      EXPECT_NEAR(levels.back().num_faces(), t, 0.1 * t) << name;
      EXPECT_TRUE(check_manifold(levels.back().F, levels.back().num_vertices()).manifold()) << name;
    }
    const int loops = static_cast<int>(boundary_loops(levels[0].F).size());
    EXPECT_EQ(loops, name == "skirt" ? 2 : 4) << name;  // waist + hem; or neck, hem, two arms
    for (size_t k = 1; k < levels.size(); ++k) {
      EXPECT_EQ(static_cast<int>(boundary_loops(levels[k].F).size()), loops) << name;
      // Same shape: levels sample one surface and differ only by the coarse level's chord
      // error, worst on thin tubes (cuffs) and cut borders: under 1 cm at these levels
      // (2-4 mm for the tops; a fifth to a third of the coarse edge length).
      EXPECT_LT(test::hausdorff_distance(levels[0], levels[k]), 0.01) << name;
      // Mean edge length scales as 1 / sqrt(triangles).
      const double ratio = mean_edge_length(levels[k].V, levels[k].F) / mean_edge_length(levels[0].V, levels[0].F);
      const double expect = std::sqrt(double(levels[0].num_faces()) / levels[k].num_faces());
      EXPECT_NEAR(ratio, expect, 0.05 * expect) << name;
    }
  }
  EXPECT_THROW(garment_template_surface("cape", f.body, mannequin_config()), Error);
}

TEST(GarmentImport, TriangleSoupWeldsAndRemeshesToEachLevel) {
  // A 12 x 12 grid bent into a half cylinder, written with three fresh vertices per face.
  const TriMesh grid = test::grid_mesh(12, 1.0);
  std::string obj;
  for (int f = 0; f < grid.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Eigen::RowVector3d p = grid.V.row(grid.F(f, k));
      const double a = p.x() * M_PI;
      obj += "v " + std::to_string(0.3 * std::cos(a)) + " " + std::to_string(p.z()) + " " +
             std::to_string(0.3 * std::sin(a)) + "\n";
    }
  for (int f = 0; f < grid.num_faces(); ++f)
    obj += "f " + std::to_string(3 * f + 1) + " " + std::to_string(3 * f + 2) + " " + std::to_string(3 * f + 3) + "\n";
  const std::string path = test::temp_dir("soup") + "/soup.obj";
  test::write_file(path, obj);
  for (int t : {300, 500, 800}) {
    const TriMesh m = import_garment(path, t);
    EXPECT_NEAR(m.num_faces(), t, 0.1 * t);
    int components = 0;
    connected_components(m.F, m.num_vertices(), &components);
    EXPECT_EQ(components, 1) << "welded";
    EXPECT_EQ(boundary_loops(m.F).size(), 1u);
    EXPECT_NEAR(face_areas(m.V, m.F).sum(), 0.3 * M_PI, 0.02);
  }
  EXPECT_THROW(import_garment(test::temp_dir("none") + "/missing.obj", 100), Error);
}

TEST(SkinWeightTransfer, CopiesTheNearestBodyVertex) {
  const Body& body = fixture().body;
  Eigen::MatrixXd V = body.mesh.V.topRows(20);
  V.col(0).array() += 1e-4;
  const Eigen::MatrixXd W = transfer_skin_weights(V, body);
  EXPECT_LT((W - body.weights.topRows(20)).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(SkinWeightTransfer, SmoothingKeepsRowsNormalisedAndSpreadsAStep) {
  // A strip whose left half follows joint 0 and right half joint 1: diffused, the switch
  // spreads over about the smoothing length and every row still sums to 1.
  const TriMesh grid = test::grid_mesh(40, 1.0);  // xz plane, [0, 1]^2, edge 0.025 m
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(grid.V.rows(), 2);
  for (Eigen::Index i = 0; i < W.rows(); ++i) W(i, grid.V(i, 0) < 0.5 ? 0 : 1) = 1;
  const Eigen::MatrixXd S = smooth_skin_weights(grid, W, 0.1);
  EXPECT_LT((S.rowwise().sum().array() - 1).abs().maxCoeff(), 1e-12);
  double at_switch = 0, far_left = 0;
  for (Eigen::Index i = 0; i < S.rows(); ++i) {
    if (std::abs(grid.V(i, 0) - 0.5) < 0.02) at_switch = std::max(at_switch, std::abs(S(i, 0) - 0.5));
    if (grid.V(i, 0) < 0.1) far_left = std::max(far_left, 1 - S(i, 0));
  }
  EXPECT_LT(at_switch, 0.25) << "the switch is blended";
  EXPECT_LT(far_left, 0.02) << "0.4 m from the switch the weights are still the nearest bone's";
  EXPECT_EQ((smooth_skin_weights(grid, W, 0.0) - W).cwiseAbs().maxCoeff(), 0.0);
}

// LBS frames of a walk: with inpainted, smoothed weights a skirt stretches no more than 3x a
// t-shirt (nearest-vertex weights tear it between the legs: ~1400 J). The long dress, which
// hugs the thighs, still stretches ~50x a t-shirt (4.3 J; raw weights 6200 J): bounded here at
// 1/100 of its raw-weight stretch, the 3x is not met yet (docs/training.md).
TEST(SkinWeightTransfer, SmoothWeightsGiveSkirtsAndDressesAPlausibleLbsFrame) {
  const Fixture& f = fixture();
  MotionParams walk;
  walk.frames = 40;
  const Motion motion = procedural_motion(f.body.skeleton, f.body.bind, walk);
  auto max_stretch = [&](const std::string& name, const SkinWeightOptions& skin) {
    const Garment g = make_garment(name, f.surfaces.at(name), f.body, kLevels[0], skin);
    const ClothGeometry cloth = make_cloth_geometry(g.mesh);
    double worst = 0;
    for (int t = 5; t < motion.num_frames(); t += 5) {
      const LbsFrame frame = lbs_frame(f.body, g, motion, t, 0.004);
      worst = std::max(worst, stretch_energy(matrix_to_tensor(frame.garment), cloth, Material{}).item<double>());
    }
    return worst;
  };
  if (std::getenv("PB4U_SKIN_SWEEP")) {
    for (double inpaint : {0.0, 0.02, 0.03, 0.05})
      for (double smooth : {0.0, 0.05, 0.1})
        std::printf("[sweep inpaint %.2f smooth %.2f] tshirt %.3g long_sleeve %.3g tank_top %.3g skirt %.3g dress %.3g\n",
                    inpaint, smooth, max_stretch("tshirt", {smooth, inpaint}), max_stretch("long_sleeve", {smooth, inpaint}),
                    max_stretch("tank_top", {smooth, inpaint}), max_stretch("skirt", {smooth, inpaint}),
                    max_stretch("long_dress", {smooth, inpaint}));
  }
  const SkinWeightOptions skin;  // the defaults generate uses
  const double tshirt = max_stretch("tshirt", skin);
  const double skirt = max_stretch("skirt", skin), dress = max_stretch("long_dress", skin);
  const double raw_skirt = max_stretch("skirt", {0.0, 0.0}), raw_dress = max_stretch("long_dress", {0.0, 0.0});
  std::printf("[lbs stretch] tshirt %.3g J, skirt %.3g J (raw weights %.3g J), long_dress %.3g J (raw %.3g J)\n",
              tshirt, skirt, raw_skirt, dress, raw_dress);
  EXPECT_LE(skirt, 3 * tshirt);
  EXPECT_LE(dress, 0.01 * raw_dress);
  EXPECT_GT(raw_skirt, 10 * skirt) << "the test can tell raw weights from smooth ones";
}

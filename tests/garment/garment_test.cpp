// Garment templates (no penetration, same shape at every level, triangle counts, edge-length
// scaling), imported triangle soups, weight transfer, clipping.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "mesh_distance.h"
#include "pb4u/body/humanoid.h"
#include "pb4u/garment/clip_mesh.h"
#include "pb4u/garment/garment_template.h"
#include "pb4u/garment/import_garment.h"
#include "pb4u/garment/skin_weight_transfer.h"
#include "pb4u/mesh/geometry.h"
#include "pb4u/mesh/topology.h"
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

const std::vector<int> kLevels = {400, 660, 900};

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
      // Same shape: coarse levels are chords of the same surface, a few mm apart.
      EXPECT_LT(test::hausdorff_distance(levels[0], levels[k]), 0.012) << name;
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

// Closed forms and invariances of the six physics terms (SPEC 3).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "pb4u/mesh/geometry.h"
#include "pb4u/physics/bending_energy.h"
#include "pb4u/physics/collision_energy.h"
#include "pb4u/physics/friction_energy.h"
#include "pb4u/physics/gravity_energy.h"
#include "pb4u/physics/inertia_energy.h"
#include "pb4u/physics/stretch_energy.h"
#include "physics_test_util.h"
#include "test_util.h"

namespace pb4u {
namespace {

using test::positions_tensor;

TriMesh one_triangle() {
  TriMesh m;
  m.V.resize(3, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 0, 1;
  m.F.resize(1, 3);
  m.F << 0, 1, 2;
  return m;
}

// A crumpled grid: curved rest shape so rigid-motion checks are not trivially flat.
TriMesh wavy_grid(int n) {
  TriMesh m = test::grid_mesh(n, 1.0);
  for (int i = 0; i < m.V.rows(); ++i) m.V(i, 1) = 0.1 * std::sin(3 * m.V(i, 0)) * std::cos(2 * m.V(i, 2));
  return m;
}

Eigen::Matrix3d some_rotation() {
  return Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, -0.5).normalized()).toRotationMatrix();
}

TEST(Stretch, ZeroAtRestAndUnderRigidMotion) {
  TriMesh m = wavy_grid(4);
  ClothGeometry cloth = make_cloth_geometry(m);
  Material mat;
  EXPECT_NEAR(stretch_energy(positions_tensor(m.V), cloth, mat).item<double>(), 0.0, 1e-12);
  Eigen::MatrixXd moved = (m.V * some_rotation().transpose()).rowwise() + Eigen::RowVector3d(3, -1, 2);
  EXPECT_NEAR(stretch_energy(positions_tensor(moved), cloth, mat).item<double>(), 0.0, 1e-10);
  // A non-rigid change is not free: the test would notice a term that is always zero.
  Eigen::MatrixXd scaled = m.V * 1.01;
  EXPECT_GT(stretch_energy(positions_tensor(scaled), cloth, mat).item<double>(), 1e-6);
}

TEST(Stretch, UniaxialAndEquibiaxialClosedForm) {
  TriMesh m = one_triangle();
  ClothGeometry cloth = make_cloth_geometry(m);
  Material mat;
  const double area = 0.5;
  for (double s : {0.8, 1.1, 1.5}) {
    double g = (s * s - 1) / 2;
    Eigen::MatrixXd uni = m.V;
    uni.col(0) *= s;
    double expect_uni = area * mat.thickness * (mat.mu * g * g + 0.5 * mat.lambda * g * g);
    EXPECT_NEAR(stretch_energy(positions_tensor(uni), cloth, mat).item<double>(), expect_uni,
                1e-10 * expect_uni);
    Eigen::MatrixXd bi = m.V * s;
    double expect_bi = area * mat.thickness * (2 * mat.mu * g * g + 2 * mat.lambda * g * g);
    EXPECT_NEAR(stretch_energy(positions_tensor(bi), cloth, mat).item<double>(), expect_bi,
                1e-10 * expect_bi);
  }
}

// Two unit-edge triangles sharing the x axis; the second is folded by phi about it.
TriMesh hinge(double phi) {
  TriMesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0.5, 0, -1, 0.5, std::sin(phi), std::cos(phi);
  m.F.resize(2, 3);
  m.F << 0, 1, 2, 1, 0, 3;
  return m;
}

TEST(Bending, ZeroForFlatSheetAndRigidMotion) {
  TriMesh flat = test::grid_mesh(4, 1.0);
  ClothGeometry cloth = make_cloth_geometry(flat);
  Material mat;
  EXPECT_NEAR(bending_energy(positions_tensor(flat.V), cloth, mat, 1e-14).item<double>(), 0.0, 1e-20);
  TriMesh m = wavy_grid(4);
  ClothGeometry wavy = make_cloth_geometry(m, torch::kFloat64, torch::kCPU, /*rest angles*/ true);
  Eigen::MatrixXd moved = (m.V * some_rotation().transpose()).rowwise() + Eigen::RowVector3d(1, 2, 3);
  EXPECT_NEAR(bending_energy(positions_tensor(moved), wavy, mat, 1e-14).item<double>(), 0.0, 1e-16);
  // Against a flat rest shape the same curved sheet does bend.
  EXPECT_GT(bending_energy(positions_tensor(m.V), make_cloth_geometry(m), mat, 1e-14).item<double>(), 1e-9);
}

TEST(Bending, HingeClosedFormIncludingNear180Degrees) {
  Material mat;
  ClothGeometry cloth = make_cloth_geometry(hinge(0.0));
  ASSERT_EQ(cloth.hinges.size(0), 1);
  // l = 1, A0 = A1 = 1/2: E = k_b * 1 / (4 * 1) * phi^2 / 2.
  for (double phi : {0.3, 1.0, 2.5, M_PI - 1e-3, M_PI - 1e-7}) {
    torch::Tensor x = positions_tensor(hinge(phi).V).requires_grad_(true);
    double theta = dihedral_angles(x, cloth.hinges, 1e-14).item<double>();
    EXPECT_NEAR(std::abs(theta), phi, 1e-9) << phi;
    torch::Tensor E = bending_energy(x, cloth, mat, 1e-14);
    double expect = mat.bending / 4.0 * phi * phi / 2.0;
    EXPECT_NEAR(E.item<double>(), expect, 1e-9 * expect) << phi;
    E.backward();
    EXPECT_TRUE(torch::isfinite(x.grad()).all().item<bool>()) << phi;
  }
  // Folding the other way gives the opposite angle.
  double a = dihedral_angles(positions_tensor(hinge(0.4).V), cloth.hinges, 1e-14).item<double>();
  double b = dihedral_angles(positions_tensor(hinge(-0.4).V), cloth.hinges, 1e-14).item<double>();
  EXPECT_NEAR(a, -b, 1e-12);
}

TEST(Bending, RestAnglesMakeTheFoldedHingeRestful) {
  Material mat;
  TriMesh folded = hinge(1.2);
  ClothGeometry cloth = make_cloth_geometry(folded, torch::kFloat64, torch::kCPU, true);
  EXPECT_NEAR(std::abs(cloth.rest_angle[0].item<double>()), 1.2, 1e-12);
  EXPECT_NEAR(bending_energy(positions_tensor(folded.V), cloth, mat, 1e-14).item<double>(), 0.0, 1e-20);
  double flat = bending_energy(positions_tensor(hinge(0.0).V), cloth, mat, 1e-14).item<double>();
  EXPECT_NEAR(flat, mat.bending / 4.0 * 1.2 * 1.2 / 2.0, 1e-12);
}

TEST(Bending, CollapsedFaceGivesFiniteEnergyAndGradient) {
  TriMesh m = hinge(0.5);
  ClothGeometry cloth = make_cloth_geometry(m);
  Eigen::MatrixXd V = m.V;
  V.row(3) = V.row(0);  // face 1 collapses onto the edge
  torch::Tensor x = positions_tensor(V).requires_grad_(true);
  torch::Tensor E = bending_energy(x, cloth, Material{}, 1e-14);
  E.backward();
  EXPECT_TRUE(std::isfinite(E.item<double>()));
  EXPECT_TRUE(torch::isfinite(x.grad()).all().item<bool>());
}

TEST(Gravity, EqualsSumOfMassTimesGTimesHeight) {
  TriMesh m = wavy_grid(3);
  Material mat;
  Eigen::VectorXd mass = vertex_masses(m.V, m.F, mat.density);
  ClothGeometry cloth = make_cloth_geometry(m);
  double g[3] = {0, -9.81, 0};
  double expect = (mass.array() * 9.81 * m.V.col(1).array()).sum();
  double got = gravity_energy(positions_tensor(m.V), cloth.vertex_masses(mat.density), g).item<double>();
  EXPECT_NEAR(got, expect, 1e-12 * std::abs(expect) + 1e-15);
  // Another gravity direction: E = -sum m g.x.
  double g2[3] = {2.0, 0.0, -1.0};
  double expect2 = -(mass.array() * (2.0 * m.V.col(0).array() - m.V.col(2).array())).sum();
  got = gravity_energy(positions_tensor(m.V), cloth.vertex_masses(mat.density), g2).item<double>();
  EXPECT_NEAR(got, expect2, 1e-12 * std::abs(expect2));
}

TEST(Inertia, ZeroOnBallisticPredictionQuadraticOffIt) {
  TriMesh m = wavy_grid(3);
  ClothGeometry cloth = make_cloth_geometry(m);
  Material mat;
  torch::Tensor x = positions_tensor(m.V);
  torch::Tensor x_prev = x - torch::tensor({0.01, -0.02, 0.005}, torch::kFloat64);
  torch::Tensor masses = cloth.vertex_masses(mat.density);
  double dt = 1.0 / 30;
  torch::Tensor ballistic = 2 * x - x_prev;
  EXPECT_NEAR(inertia_energy(ballistic, x, x_prev, masses, dt).item<double>(), 0.0, 1e-18);
  torch::Tensor delta = torch::tensor({0.003, 0.0, -0.004}, torch::kFloat64);  // |delta| = 5 mm
  double total_mass = masses.sum().item<double>();
  double expect = total_mass * 25e-6 / (2 * dt * dt);
  EXPECT_NEAR(inertia_energy(ballistic + delta, x, x_prev, masses, dt).item<double>(), expect, 1e-12 * expect);
}

// The body is a large flat grid at y = 0 with normal +y.
BodyFrame floor_body() {
  TriMesh floor = test::grid_mesh(4, 20.0);
  floor.V.col(0).array() -= 10.0;
  floor.V.col(2).array() -= 10.0;
  return test::static_body(floor);
}

TEST(Collision, ZeroBeyondEpsCubicInside) {
  const double eps = 2e-3, w = 5e5;
  BodyFrame body = floor_body();
  auto energy_at = [&](double height) {
    torch::Tensor x = torch::tensor({{0.3, height, -0.2}}, torch::kFloat64);
    BodyContact c = query_body_contact(x, body, 5e-3, 1e-14);
    return collision_energy(x, c, eps, w).item<double>();
  };
  EXPECT_EQ(energy_at(eps + 1e-6), 0.0);
  EXPECT_EQ(energy_at(0.5), 0.0);
  for (double d : {1e-3, 0.0, -4e-3}) EXPECT_NEAR(energy_at(d), w * std::pow(eps - d, 3), 1e-12);
}

TEST(Collision, UsesTheNextBodyPose) {
  BodyFrame body = floor_body();
  body.next_vertices = body.vertices + torch::tensor({0.0, 0.01, 0.0}, torch::kFloat64);  // rises 1 cm
  torch::Tensor x = torch::tensor({{0.3, 0.005, -0.2}}, torch::kFloat64);
  BodyContact c = query_body_contact(x, body, 5e-3, 1e-14);
  double d = 0.005 - 0.01;
  EXPECT_NEAR(collision_energy(x, c, 2e-3, 5e5).item<double>(), 5e5 * std::pow(2e-3 - d, 3), 1e-12);
}

// Measured again against some of the body's faces, a contact keeps the degenerate area its
// query was made with: below it (the floor's faces: 2 x area = 25 m^2 each), their normals
// stay unnormalised, |n| = 25 / 100, in the query and in the measure against the faces.
TEST(Collision, ContactOnFacesKeepsTheQuerysDegenerateArea) {
  BodyFrame body = floor_body();
  torch::Tensor x = torch::tensor({{0.3, 0.005, -0.2}, {-4.0, 0.02, 3.0}}, torch::kFloat64);
  const double degenerate = 100.0, twice_area = std::pow(20.0 / 4, 2);
  BodyContact c = query_body_contact(x, body, 5e-3, degenerate);
  EXPECT_EQ(c.degenerate_area, degenerate);
  std::vector<int64_t> rows(body.faces.size(0));
  for (size_t f = 0; f < rows.size(); ++f) rows[f] = int64_t(f);
  BodyContact on_faces = contact_on_faces(c, x, body, rows);
  EXPECT_EQ(on_faces.degenerate_area, degenerate);
  EXPECT_TRUE(torch::equal(on_faces.face, c.face));
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(on_faces.normal[i].norm().item<double>(), twice_area / degenerate, 1e-12);
    EXPECT_NEAR(on_faces.normal[i][1].item<double>(), twice_area / degenerate, 1e-12);
  }
}

TEST(Friction, ZeroWhenMovingWithTheBodyAndClosedFormWhenSliding) {
  TriMesh g = test::grid_mesh(2, 0.2);
  g.V.col(1).array() += 1e-3;  // resting 1 mm above the floor: in contact
  ClothGeometry cloth = make_cloth_geometry(g);
  Material mat;
  torch::Tensor masses = cloth.vertex_masses(mat.density);
  torch::Tensor x = positions_tensor(g.V);
  BodyFrame body = floor_body();
  torch::Tensor shift = torch::tensor({0.02, 0.0, -0.01}, torch::kFloat64);
  body.next_vertices = body.vertices + shift;
  BodyContact c = query_body_contact(x, body, 5e-3, 1e-14);
  ASSERT_TRUE(c.in_contact.all().item<bool>());
  const double mu = 0.5, smooth = 1e-6, gn = 9.81;
  EXPECT_NEAR(friction_energy(x + shift, x, masses, c, mu, gn, smooth).item<double>(), 0.0, 1e-15);
  // Sliding 3 cm over the moving floor, plus a normal motion that friction ignores.
  torch::Tensor x_next = x + shift + torch::tensor({0.0, 0.01, 0.03}, torch::kFloat64);
  double slip = std::sqrt(0.03 * 0.03 + smooth * smooth) - smooth;
  double expect = mu * gn * masses.sum().item<double>() * slip;
  EXPECT_NEAR(friction_energy(x_next, x, masses, c, mu, gn, smooth).item<double>(), expect, 1e-12 * expect);
  // Out of contact: no friction.
  BodyContact far = query_body_contact(x + torch::tensor({0.0, 0.5, 0.0}, torch::kFloat64), body, 5e-3, 1e-14);
  EXPECT_FALSE(far.in_contact.any().item<bool>());
  EXPECT_EQ(friction_energy(x_next, x, masses, far, mu, gn, smooth).item<double>(), 0.0);
}

TEST(Friction, TangentPlaneIsTheBodySurfaceNotAFixedAxis) {
  // A wall (normal +x): sliding along y is tangential there, moving along x is not.
  TriMesh wall = test::grid_mesh(2, 4.0);
  Eigen::MatrixXd V = wall.V;
  wall.V.col(0) = V.col(1);
  wall.V.col(1) = 2.0 - V.col(0).array();  // (x, y, z) -> (y, -x, z): a rotation taking +y to +x
  wall.V.col(2) = V.col(2).array() - 2.0;
  BodyFrame body = test::static_body(wall);
  torch::Tensor x = torch::tensor({{1e-3, 0.1, 0.1}}, torch::kFloat64);
  BodyContact c = query_body_contact(x, body, 5e-3, 1e-14);
  ASSERT_NEAR(c.normal[0][0].item<double>(), 1.0, 1e-12);
  torch::Tensor m = torch::tensor({0.01}, torch::kFloat64);
  double along_normal = friction_energy(x + torch::tensor({0.02, 0.0, 0.0}, torch::kFloat64), x, m, c, 0.5, 9.81, 1e-6).item<double>();
  double along_wall = friction_energy(x + torch::tensor({0.0, -0.02, 0.0}, torch::kFloat64), x, m, c, 0.5, 9.81, 1e-6).item<double>();
  EXPECT_NEAR(along_normal, 0.0, 1e-15);
  EXPECT_NEAR(along_wall, 0.5 * 9.81 * 0.01 * (std::sqrt(0.02 * 0.02 + 1e-12) - 1e-6), 1e-15);
}

}  // namespace
}  // namespace pb4u

// Near-degenerate geometry at the level of single terms and features (issue 9): sliver rest
// triangles, hinges folded to within a hair of 180 degrees (and exactly), and triangles
// collapsed to a point in the current state. Every energy, its gradient and every network
// input must be finite; the dihedral angle must approach +-pi continuously.
#include <gtest/gtest.h>

#include <cmath>

#include "hard_case.h"
#include "test_util.h"
#include "pb4u/graph/build_graph.h"
#include "pb4u/physics/bending_energy.h"
#include "pb4u/physics/body_queries.h"
#include "pb4u/physics/energy_report.h"
#include "pb4u/util/eigen_tensor.h"

namespace pb4u {
namespace {

// Every active term's energy and gradient at x_next, finite; returns the total.
double expect_finite_terms(const std::string& label, const TriMesh& rest, const torch::Tensor& x_next,
                           const FrameState& state) {
  PhysicsConfig physics;
  ClothGeometry cloth = make_cloth_geometry(rest, torch::kFloat64, torch::kCPU, true, physics.degenerate_area);
  TermList terms = build_terms(state.effects, physics);
  std::optional<BodyContact> contact = body_contact_for(state, physics);
  double total = 0;
  for (auto& [name, e] : term_energies(terms, x_next, state, cloth, contact ? &*contact : nullptr)) {
    EXPECT_TRUE(std::isfinite(e.item<double>())) << label << " " << name;
    auto g = torch::autograd::grad({e}, {x_next}, {}, true, false, true)[0];
    if (g.defined()) EXPECT_TRUE(torch::isfinite(g).all().item<bool>()) << label << " gradient of " << name;
    total += e.item<double>();
  }
  return total;
}

FrameState still_state(const Eigen::MatrixXd& x, const std::vector<std::string>& effects) {
  FrameState s;
  s.x = s.x_prev = matrix_to_tensor(x);
  s.effects = Effects::from_names(effects, "test");
  return s;
}

void expect_finite_graph(const std::string& label, const TriMesh& rest, const FrameState& state) {
  GarmentTopology topology = build_garment_topology(rest, label);
  GraphBatch g = build_graph(state, topology, hard::shipped_model().config.graph_options());
  for (const torch::Tensor* t : {&g.node_features, &g.mesh_features})
    EXPECT_TRUE(torch::isfinite(*t).all().item<bool>()) << label;
  Pb4uNet net = hard::shipped_model().model;  // a handle: step() is not const
  torch::Tensor x_next = net->step(state, topology);
  EXPECT_TRUE(torch::isfinite(x_next).all().item<bool>()) << label;
}

TEST(DegenerateGeometry, SliverRestTrianglesUnderLoad) {
  TriMesh rest = test::lattice_cloth(6, 6, 0.03, 2, 1e-8);  // areas ~ 1.5e-10 m^2
  Eigen::MatrixXd x = rest.V;
  x.col(1) *= 1.05;  // stretched 5% vertically: the sliver strip's Dm^-1 ~ 1e8 /m amplifies it
  x(14, 2) = 1e-3;   // and one vertex pushed out of plane
  FrameState state = still_state(rest.V, {"gravity"});
  torch::Tensor x_next = matrix_to_tensor(x).requires_grad_(true);
  EXPECT_GT(expect_finite_terms("sliver", rest, x_next, state), 0.0);
  expect_finite_graph("sliver", rest, state);
}

TEST(DegenerateGeometry, HingesFoldedToPiStayFiniteAndContinuous) {
  TriMesh rest;
  rest.V.resize(4, 3);
  rest.V << 0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -1, 0;
  rest.F.resize(2, 3);
  rest.F << 0, 1, 2, 1, 0, 3;
  ClothGeometry cloth = make_cloth_geometry(rest);
  for (double eps : {1e-2, 1e-5, 1e-8, 0.0}) {
    for (double side : {1.0, -1.0}) {
      // Vertex 3 swung about the shared edge until it nearly lies on top of vertex 2.
      Eigen::MatrixXd x = rest.V;
      x.row(3) << 0.5, std::cos(eps), side * std::sin(eps);
      torch::Tensor xt = matrix_to_tensor(x).requires_grad_(true);
      torch::Tensor theta = dihedral_angles(xt, cloth.hinges, 1e-14);
      const double t = theta.item<double>();
      EXPECT_TRUE(std::isfinite(t));
      EXPECT_NEAR(std::abs(t), M_PI - eps, 1e-7) << eps;
      auto g = torch::autograd::grad({theta.sum()}, {xt})[0];
      EXPECT_TRUE(torch::isfinite(g).all().item<bool>()) << eps;
      FrameState state = still_state(rest.V, {});
      EXPECT_TRUE(std::isfinite(expect_finite_terms("fold", rest, xt, state)));
    }
  }
}

TEST(DegenerateGeometry, TrianglesCollapsedToAPointInTheCurrentState) {
  TriMesh rest = test::lattice_cloth(5, 5, 0.03);
  Eigen::MatrixXd x = rest.V;
  // Face 0's three vertices on one point: zero area, zero-length edges, undefined normal.
  for (int k = 1; k < 3; ++k) x.row(rest.F(0, k)) = x.row(rest.F(0, 0));
  FrameState state = still_state(x, {"gravity"});
  torch::Tensor x_next = matrix_to_tensor(x).requires_grad_(true);
  EXPECT_GT(expect_finite_terms("collapsed", rest, x_next, state), 0.0);
  expect_finite_graph("collapsed", rest, state);
}

TEST(DegenerateGeometry, BodyFacesCollapsedAndGarmentInsideTheBody) {
  // A body with a zero-area face and the garment entirely inside it: collision and friction
  // must stay finite (degenerate body normals are not normalised by zero).
  TriMesh rest = test::lattice_cloth(4, 4, 0.02);
  Eigen::MatrixXd bv;
  Eigen::MatrixXi bf;
  hard::box_mesh(rest.V.colwise().mean().transpose(), 0.2, &bv, &bf);
  bv.row(7) = bv.row(6);  // faces through vertices 6 and 7 lose area
  FrameState state = still_state(rest.V, {"gravity", "collision", "friction"});
  state.body.vertices = state.body.next_vertices = matrix_to_tensor(bv);
  state.body.faces = index_matrix_to_tensor(bf);
  torch::Tensor x_next = matrix_to_tensor(rest.V).requires_grad_(true);
  EXPECT_GT(expect_finite_terms("inside body", rest, x_next, state), 0.0);
}

TEST(UnseenInputs, AFeatureConstantInTrainingIsCentredNotAmplified) {
  // Column 0 varies, columns 1 and 2 never do (like the pinned vertex type, which training
  // never samples). A new value must come out centred, not divided by the 1e-8 floor.
  OnlineNormalizer norm(3, 10, 1e-8);
  norm->train();
  for (int k = 0; k < 4; ++k) norm->forward(torch::tensor({{double(k), 0.0, 5.0}, {double(-k), 0.0, 5.0}}));
  norm->eval();
  torch::Tensor out = norm->forward(torch::tensor({{1.0, 1.0, 6.0}}));
  const double std0 = std::sqrt((0 + 0 + 1 + 1 + 4 + 4 + 9 + 9) / 8.0);
  EXPECT_NEAR(out[0][0].item<double>(), 1.0 / std0, 1e-6);
  EXPECT_NEAR(out[0][1].item<double>(), 1.0, 1e-6);
  EXPECT_NEAR(out[0][2].item<double>(), 1.0, 1e-6);
  // The shipped model trained with pins (effects.p_pins): its normaliser saw the pinned
  // vertex type (feature 8) and the pins effect flag (17) vary. (The model shipped before
  // issue 14 never had: its std there was the unit of a constant feature, exactly 1.)
  torch::Tensor s = hard::shipped_model().model->vertex_normalizer->std();
  for (int f : {8, 17}) {
    EXPECT_GT(s[f].item<double>(), 0.0) << "feature " << f;
    EXPECT_LT(s[f].item<double>(), 0.5) << "feature " << f << " varied in training";
  }
}

}  // namespace
}  // namespace pb4u

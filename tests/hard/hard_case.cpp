#include "hard_case.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>

#include "pb4u/mesh/edges.h"
#include "pb4u/mesh/geometry.h"
#include "pb4u/scene/pins.h"

namespace pb4u::hard {

int scale() {
  const char* s = std::getenv("PB4U_HARD_SCALE");
  return s && std::atoi(s) > 1 ? std::atoi(s) : 1;
}

const ModelFile& shipped_model() {
  static const ModelFile m = load_model_file(std::string(PB4U_TEST_DATA) + "/pretrained/pb4u.h5");
  return m;
}

ModelFile untrained_model(double lbar_base) {
  torch::manual_seed(9);
  ModelFile m;
  m.config.latent = 32;
  m.config.num_blocks = 2;
  m.config.k_base = 2;
  m.model = Pb4uNet(m.config);
  m.model->calibrate(lbar_base);
  m.model->eval();
  m.source = "untrained";
  return m;
}

TriMesh lattice_cloth(int res_x, int res_y, double dx, int thin_row, double thin_height) {
  const double dy = dx * std::sqrt(3.0) / 2;
  TriMesh m;
  m.V.resize(res_x * res_y, 3);
  double y = 1.0;
  for (int r = 0; r < res_y; ++r) {
    for (int c = 0; c < res_x; ++c) m.V.row(r * res_x + c) << c * dx + (r % 2) * dx / 2, y, 0.0;
    y -= r == thin_row ? thin_height : dy;
  }
  m.F.resize(2 * (res_x - 1) * (res_y - 1), 3);
  int f = 0;
  for (int r = 0; r + 1 < res_y; ++r)
    for (int c = 0; c + 1 < res_x; ++c) {
      const int t0 = r * res_x + c, t1 = t0 + 1, b0 = t0 + res_x, b1 = b0 + 1;
      // Rows go down (-y) and columns right (+x): (t, b, ...) counter-clockwise seen from +z.
      if (r % 2 == 0) {
        m.F.row(f++) << t0, b0, t1;
        m.F.row(f++) << t1, b0, b1;
      } else {
        m.F.row(f++) << t0, b0, b1;
        m.F.row(f++) << t0, b1, t1;
      }
    }
  return m;
}

void box_mesh(const Eigen::Vector3d& c, double h, Eigen::MatrixXd* V, Eigen::MatrixXi* F) {
  V->resize(8, 3);
  for (int i = 0; i < 8; ++i)
    V->row(i) << c.x() + (i & 1 ? h : -h), c.y() + (i & 2 ? h : -h), c.z() + (i & 4 ? h : -h);
  F->resize(12, 3);
  *F << 0, 2, 1, 1, 2, 3,   // z-
      4, 5, 6, 5, 7, 6,     // z+
      0, 1, 4, 1, 5, 4,     // y-
      2, 6, 3, 3, 6, 7,     // y+
      0, 4, 2, 2, 4, 6,     // x-
      1, 3, 5, 3, 7, 5;     // x+
}

RolloutInput still_start(const TriMesh& garment, const Effects& effects, const Material& material, int steps) {
  RolloutInput in;
  in.garment_rest = garment;
  in.x0 = in.x_prev = garment.V;
  in.effects = effects;
  in.material = in.metric_material = material;
  in.steps = steps;
  if (effects.pins) in.pinned = top_band_vertices(garment.V, 1e-6);
  return in;
}

Bounds finite_only() {
  Bounds b;
  b.max_stretch = 0;
  b.energy_guard = false;
  return b;
}

RolloutFigures check_rollout(const std::string& label, const RolloutInput& input, const StepFunction& step,
                             const PhysicsConfig& physics, const Bounds& bounds) {
  RolloutInput in = input;
  if (!bounds.energy_guard) in.divergence.energy_ratio = 0;
  const TriMesh& rest = in.garment_rest;
  const Eigen::MatrixXi E = unique_edges(rest.F);
  const Eigen::VectorXd L = edge_lengths(rest.V, E);
  // Edges with at least one face of positive rest area (the others have no material).
  std::vector<bool> checked(E.rows(), !bounds.skip_zero_area_edges);
  if (bounds.skip_zero_area_edges) {
    const Eigen::VectorXd A = face_areas(rest.V, rest.F);
    std::map<std::pair<int, int>, int> index;
    for (int e = 0; e < E.rows(); ++e) index[{E(e, 0), E(e, 1)}] = e;
    for (int f = 0; f < rest.F.rows(); ++f)
      for (int k = 0; k < 3; ++k) {
        int a = rest.F(f, k), b = rest.F(f, (k + 1) % 3);
        if (A(f) > 0) checked[index.at({std::min(a, b), std::max(a, b)})] = true;
      }
  }
  RolloutFigures fig;
  Eigen::MatrixXd prev = in.x0;
  auto t0 = std::chrono::steady_clock::now();
  RolloutResult r = run_rollout(in, step, physics, [&](int frame, const Eigen::MatrixXd& x, const EnergyReport& rep,
                                                      const PenetrationFigures*) {
    ++fig.frames;
    EXPECT_TRUE(x.allFinite()) << label << " frame " << frame;
    EXPECT_TRUE(std::isfinite(rep.total)) << label << " frame " << frame;
    for (const auto& [name, value] : rep.terms) {
      EXPECT_TRUE(std::isfinite(value)) << label << " frame " << frame << " " << name;
      if (name != "gravity") EXPECT_GE(value, 0.0) << label << " frame " << frame << " " << name;
    }
    fig.max_total = std::max(fig.max_total, rep.total);
    const double speed = (x - prev).rowwise().norm().maxCoeff() / in.dt;
    fig.max_speed = std::max(fig.max_speed, speed);
    if (bounds.max_speed > 0 && speed > bounds.max_speed)
      ADD_FAILURE() << label << " frame " << frame << ": a vertex moves at " << speed << " m/s";
    prev = x;
    for (int e = 0; e < E.rows(); ++e) {
      if (!checked[e] || !(L(e) > 0)) continue;
      double ratio = (x.row(E(e, 0)) - x.row(E(e, 1))).norm() / L(e);
      fig.max_stretch = std::max(fig.max_stretch, ratio);
      if (bounds.max_stretch > 0 && ratio > bounds.max_stretch)
        ADD_FAILURE() << label << " frame " << frame << ": edge " << E(e, 0) << "-" << E(e, 1)
                      << " stretched " << ratio << "x rest";
    }
  });
  fig.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_FALSE(r.diverged) << label << ": diverged at frame " << r.diverged_at_frame << ": " << r.diverged_reason
                           << " (vertex " << r.worst_vertex << ")";
  EXPECT_EQ(fig.frames, in.steps) << label;
  for (const EnergyReport& rep : r.reports) {
    fig.mean_positive += positive_energy(rep) / double(r.reports.size());
    fig.max_positive = std::max(fig.max_positive, positive_energy(rep));
  }
  if (!r.penetration.empty()) fig.penetration = summarize_penetration(r.penetration);
  std::printf("[hard] %s: %d frames, %lld vertices, max stretch %.3fx, max total %.4g J, positive energy mean %.4g / "
              "max %.4g J, max speed %.3g m/s, %.2f s\n",
              label.c_str(), fig.frames, static_cast<long long>(rest.V.rows()), fig.max_stretch, fig.max_total,
              fig.mean_positive, fig.max_positive, fig.max_speed, fig.seconds);
  if (fig.penetration)
    std::printf("[hard] %s: inside %.2f%% mean / %.2f%% max, deepest %.2f mm\n", label.c_str(),
                100 * fig.penetration->penetrating_fraction, 100 * fig.penetration->max_penetrating_fraction,
                fig.penetration->max_penetration_mm);
  return fig;
}

void check_relative(const std::string& label, const RolloutFigures& network, const RolloutFigures& reference,
                    const RelativeBounds& bounds) {
  if (reference.max_positive < kReferenceAtRest) {
    std::printf("[hard] %s: the reference is at rest (largest positive energy %.3g J): energy ratio undefined, "
                "network mean %.3g J, max %.3g J\n",
                label.c_str(), reference.max_positive, network.mean_positive, network.max_positive);
  } else {
    const double mean_ratio = network.mean_positive / reference.mean_positive;
    const double max_ratio = network.max_positive / reference.max_positive;
    EXPECT_LE(mean_ratio, bounds.mean_positive_ratio)
        << label << ": mean positive energy " << network.mean_positive << " J vs the reference's "
        << reference.mean_positive << " J";
    EXPECT_LE(max_ratio, bounds.max_positive_ratio)
        << label << ": largest positive energy " << network.max_positive << " J vs the reference's "
        << reference.max_positive << " J";
    std::printf("[hard] %s: positive energy / reference: mean %.3gx, max %.3gx (bounds %gx, %gx)\n", label.c_str(),
                mean_ratio, max_ratio, bounds.mean_positive_ratio, bounds.max_positive_ratio);
  }
  if (!reference.penetration) return;
  EXPECT_TRUE(network.penetration.has_value()) << label << ": no penetration measured for the network";
  if (!network.penetration) return;
  const PenetrationSummary& n = *network.penetration;
  const PenetrationSummary& r = *reference.penetration;
  EXPECT_LE(n.penetrating_fraction, r.penetrating_fraction + bounds.penetrating_fraction_margin)
      << label << ": mean share of vertices inside the body " << n.penetrating_fraction << " vs the reference's "
      << r.penetrating_fraction;
  EXPECT_LE(n.max_penetration_mm, r.max_penetration_mm + bounds.penetration_mm_margin)
      << label << ": deepest penetration " << n.max_penetration_mm << " mm vs the reference's " << r.max_penetration_mm
      << " mm";
  std::printf("[hard] %s: inside %.2f%% vs reference %.2f%% (margin %.0f points), deepest %.2f vs %.2f mm (margin %g mm)\n",
              label.c_str(), 100 * n.penetrating_fraction, 100 * r.penetrating_fraction,
              100 * bounds.penetrating_fraction_margin, n.max_penetration_mm, r.max_penetration_mm,
              bounds.penetration_mm_margin);
}

}  // namespace pb4u::hard

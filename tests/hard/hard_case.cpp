#include "hard_case.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "pb4u/config/config_io.h"
#include "pb4u/mesh/edges.h"
#include "pb4u/mesh/geometry.h"
#include "pb4u/physics/barrier_potential.h"
#include "pb4u/physics/contact_candidates.h"
#include "pb4u/rollout/refined_step.h"
#include "pb4u/scene/pins.h"

namespace pb4u::hard {
namespace {

// Three significant digits, as the printed lines have them (std::to_string keeps six decimals).
std::string num(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", value);
  return buffer;
}

}  // namespace

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
                             const PhysicsConfig& physics, const Bounds& bounds, Judge judge) {
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
  // A check that missed: a gtest failure, or counted and the first kept for the report.
  auto miss = [&](const std::string& what) {
    if (judge == Judge::kExpect) ADD_FAILURE() << label << " " << what;
    if (fig.violations++ == 0) fig.first_violation = what;
  };
  const bool free_of_body = bounds.intersection_free && !in.body.empty();
  Eigen::MatrixXd prev = in.x0;
  auto t0 = std::chrono::steady_clock::now();
  RolloutResult r = run_rollout(in, step, physics, [&](int frame, const Eigen::MatrixXd& x, const EnergyReport& rep,
                                                      const PenetrationFigures* penetration) {
    ++fig.frames;
    const std::string at = "frame " + std::to_string(frame);
    if (!x.allFinite()) miss(at + ": non-finite positions");
    if (!std::isfinite(rep.total)) miss(at + ": non-finite total energy");
    for (const auto& [name, value] : rep.terms) {
      if (!std::isfinite(value)) miss(at + ": non-finite " + name);
      if (name != "gravity" && value < 0.0) miss(at + ": negative " + name);
    }
    fig.max_total = std::max(fig.max_total, rep.total);
    const double speed = (x - prev).rowwise().norm().maxCoeff() / in.dt;
    fig.max_speed = std::max(fig.max_speed, speed);
    if (bounds.max_speed > 0 && speed > bounds.max_speed)
      miss(at + ": a vertex moves at " + num(speed) + " m/s");
    prev = x;
    for (int e = 0; e < E.rows(); ++e) {
      if (!checked[e] || !(L(e) > 0)) continue;
      double ratio = (x.row(E(e, 0)) - x.row(E(e, 1))).norm() / L(e);
      fig.max_stretch = std::max(fig.max_stretch, ratio);
      if (bounds.max_stretch > 0 && ratio > bounds.max_stretch)
        miss(at + ": edge " + std::to_string(E(e, 0)) + "-" + std::to_string(E(e, 1)) + " stretched " +
             num(ratio) + "x rest");
    }
    if (free_of_body) {
      if (penetration && penetration->penetrating_fraction > 0)
        miss(at + ": " + num(100 * penetration->penetrating_fraction) + "% of the vertices inside the body, " +
             num(penetration->max_penetration_mm) + " mm deep");
      const size_t through =
          cloth_edges_through_body(x, E, make_contact_surface(in.body[frame], in.body_faces)).size();
      if (through > 0) miss(at + ": " + std::to_string(through) + " cloth edges through the body");
    }
  });
  fig.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (r.diverged)
    miss("diverged at frame " + std::to_string(r.diverged_at_frame) + ": " + r.diverged_reason + " (vertex " +
         std::to_string(r.worst_vertex) + ")");
  if (fig.frames != in.steps) miss(std::to_string(fig.frames) + " of " + std::to_string(in.steps) + " frames");
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
    std::printf("[hard] %s: inside %.2f%% mean / %.2f%% max, deepest %.2f mm; cloth edges through the body on %d of "
                "%d frames, at most %d; the body crosses itself on %d frames (at most %d faces inside another "
                "part)\n",
                label.c_str(), 100 * fig.penetration->penetrating_fraction,
                100 * fig.penetration->max_penetrating_fraction, fig.penetration->max_penetration_mm,
                fig.penetration->frames_with_edges_through, fig.penetration->frames,
                fig.penetration->max_edges_through, fig.penetration->frames_with_body_self_crossing,
                fig.penetration->max_body_self_crossing_faces);
  if (judge == Judge::kReport && fig.violations > 0)
    std::printf("[hard] %s: outside its frame bounds %d times, first: %s\n", label.c_str(), fig.violations,
                fig.first_violation.c_str());
  return fig;
}

bool check_relative(const std::string& label, const RolloutFigures& network, const RolloutFigures& reference,
                    const RelativeBounds& bounds, Judge judge) {
  bool within = true;
  auto check = [&](bool ok, const std::string& what) {
    if (ok) return;
    within = false;
    if (judge == Judge::kExpect) ADD_FAILURE() << label << ": " << what;
  };
  if (reference.max_positive < kReferenceAtRest) {
    std::printf("[hard] %s: the reference is at rest (largest positive energy %.3g J): energy ratio undefined, "
                "network mean %.3g J, max %.3g J\n",
                label.c_str(), reference.max_positive, network.mean_positive, network.max_positive);
  } else {
    const double mean_ratio = network.mean_positive / reference.mean_positive;
    const double max_ratio = network.max_positive / reference.max_positive;
    check(mean_ratio <= bounds.mean_positive_ratio,
          "mean positive energy " + num(network.mean_positive) + " J vs the reference's " +
              num(reference.mean_positive) + " J");
    check(max_ratio <= bounds.max_positive_ratio,
          "largest positive energy " + num(network.max_positive) + " J vs the reference's " +
              num(reference.max_positive) + " J");
    std::printf("[hard] %s: positive energy / reference: mean %.3gx, max %.3gx (bounds %gx, %gx)\n", label.c_str(),
                mean_ratio, max_ratio, bounds.mean_positive_ratio, bounds.max_positive_ratio);
  }
  if (reference.penetration) {
    check(network.penetration.has_value(), "no penetration measured for the network");
    if (network.penetration) {
      const PenetrationSummary& n = *network.penetration;
      const PenetrationSummary& r = *reference.penetration;
      check(n.penetrating_fraction <= r.penetrating_fraction + bounds.penetrating_fraction_margin,
            "mean share of vertices inside the body " + num(n.penetrating_fraction) +
                " vs the reference's " + num(r.penetrating_fraction));
      check(n.max_penetration_mm <= r.max_penetration_mm + bounds.penetration_mm_margin,
            "deepest penetration " + num(n.max_penetration_mm) + " mm vs the reference's " +
                num(r.max_penetration_mm) + " mm");
      std::printf(
          "[hard] %s: inside %.2f%% vs reference %.2f%% (margin %.0f points), deepest %.2f vs %.2f mm (margin %g mm)\n",
          label.c_str(), 100 * n.penetrating_fraction, 100 * r.penetrating_fraction,
          100 * bounds.penetrating_fraction_margin, n.max_penetration_mm, r.max_penetration_mm,
          bounds.penetration_mm_margin);
    }
  }
  return within;
}

std::string body_start() {
  const char* s = std::getenv("PB4U_HARD_START");
  const std::string start = s ? s : "skinned";
  if (start != "skinned" && start != "settled")
    throw Error("PB4U_HARD_START: '" + start + "' is not skinned or settled");
  return start;
}

namespace {
// `config` with the comma-separated KEY=VALUE list in the environment variable `env`, checked
// as a config file's keys are; unchanged when `env` is unset.
template <class Config>
Config with_overrides_from(const Config& config, const char* env) {
  const char* sets = std::getenv(env);
  if (!sets) return config;
  std::vector<std::string> list;
  std::stringstream in(sets);
  for (std::string set; std::getline(in, set, ',');)
    if (!set.empty()) list.push_back(set);
  YAML::Node root = YAML::Load(config_to_yaml(config));
  std::set<std::string> overridden;
  apply_overrides(root, list, &overridden);
  Config out;
  ConfigReader reader(root, env, "", &overridden);
  out.visit(reader);
  reader.finish();
  return out;
}
}  // namespace

PhysicsConfig with_solver_overrides(const PhysicsConfig& physics) {
  PhysicsConfig p = physics;
  // scripts/hard_cases.sh --step newton: the reference solver with Newton steps.
  if (const char* step = std::getenv("PB4U_HARD_SOLVER_STEP")) p.solver.step = step;
  // scripts/hard_cases.sh --solver KEY=VALUE,...: physics.solver keys for the reference and the
  // refinement.
  p.solver = with_overrides_from(p.solver, "PB4U_HARD_SOLVER");
  return p;
}

RefineConfig with_refine_overrides(const RefineConfig& refine) {
  // scripts/hard_cases.sh --refine KEY=VALUE,...: the refinement's keys (release_held_cloth,
  // step); each run keeps its own count and tolerance.
  RefineConfig r = with_overrides_from(refine, "PB4U_HARD_REFINE");
  r.iterations = refine.iterations;
  r.tolerance_mm = refine.tolerance_mm;
  return r;
}

PhysicsConfig reference_physics(const PhysicsConfig& physics, const RolloutInput& in) {
  PhysicsConfig p = with_solver_overrides(physics);
  if (!in.body.empty() && in.effects.collision) p.solver.contact = "barrier";
  return p;
}

RolloutFigures check_reference(const std::string& label, const RolloutInput& in, const PhysicsConfig& physics,
                               Bounds bounds) {
  const PhysicsConfig p = reference_physics(physics, in);
  bounds.intersection_free = p.solver.contact == "barrier";
  return check_rollout(label + " / reference (" + p.solver.contact + " contact)", in, reference_stepper(p.solver), p,
                       bounds);
}

ShippedFigures check_shipped(const std::string& label, const RolloutInput& in, const GarmentTopology& topology,
                             const PhysicsConfig& physics, const RolloutFigures& reference, const Bounds& bounds,
                             const RelativeBounds& relative) {
  const PhysicsConfig p = reference_physics(physics, in);
  ModelFile alone = shipped_model();
  alone.config.contact_projection = 0;
  alone.config.strain_limit = 0;
  alone.config.refine_iterations = 0;
  alone.config.refine_tolerance_mm = 0;
  ShippedFigures fig;
  Bounds refined_bounds = bounds;
  refined_bounds.intersection_free = p.solver.contact == "barrier";
  auto refined_by = [&](const RefineConfig& refine) {
    return refined_stepper(network_stepper(shipped_model(), topology), p.solver, refine);
  };
  // The network alone, with its passes and refined by a fixed count: measured against the same
  // bounds, not judged.
  auto report = [&](const std::string& name, const StepFunction& step, const Bounds& b, RolloutFigures* out) {
    *out = check_rollout(label + " / " + name, in, step, p, b, Judge::kReport);
    const bool within = check_relative(label + " / " + name, *out, reference, relative, Judge::kReport);
    std::printf("[hard] %s / %s: %s\n", label.c_str(), name.c_str(),
                within && out->violations == 0 ? "within the bounds" : "OUTSIDE the bounds (reported, not judged)");
  };
  report("Pb4U alone", network_stepper(alone, topology), bounds, &fig.alone);
  report("Pb4U + passes", network_stepper(shipped_model(), topology), bounds, &fig.passes);
  RefineConfig fixed;
  fixed.iterations = kRefineIterations;
  fixed = with_refine_overrides(fixed);
  report("Pb4U + passes" + refine_label(fixed.iterations, 0), refined_by(fixed), refined_bounds,
         &fig.refined_fixed);
  RefineConfig refine = fixed;
  refine.tolerance_mm = kRefineToleranceMm;
  const std::string refined = label + " / Pb4U + passes" + refine_label(refine.iterations, refine.tolerance_mm);
  fig.refined = check_rollout(refined, in, refined_by(refine), p, refined_bounds);
  check_relative(refined, fig.refined, reference, relative);
  return fig;
}

}  // namespace pb4u::hard

#include "pb4u/rollout/rollout.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "pb4u/data/lbs_frame.h"
#include "pb4u/mesh/edges.h"
#include "pb4u/physics/barrier_potential.h"
#include "pb4u/physics/cloth_geometry.h"
#include "pb4u/physics/intersection_free_start.h"
#include "pb4u/physics/reference_solver.h"
#include "pb4u/physics/step_constraints.h"
#include "pb4u/physics/step_residual.h"
#include "pb4u/rollout/refined_step.h"
#include "pb4u/util/error.h"
#include "pb4u/util/stopwatch.h"

namespace pb4u {

RolloutInput lbs_rollout_input(const Body& body, const Garment& garment, const Motion& motion, int start,
                               int steps, const Effects& effects, const Material& material,
                               double push_out_gap) {
  LbsFrame frame = lbs_frame(body, garment, motion, start, push_out_gap);
  RolloutInput in;
  in.garment_rest = garment.mesh;
  in.x0 = frame.garment;
  in.x_prev = frame.garment_prev;
  in.effects = effects;
  in.material = material;
  in.metric_material = material;
  in.steps = steps;
  if (effects.needs_body()) {
    in.body_faces = body.mesh.F;
    for (int t = start; t <= start + steps; ++t) in.body.push_back(pose_body(body, motion.frames[t]));
  }
  return in;
}

std::vector<Eigen::MatrixXd> skinned_pin_targets(const Body& body, const Garment& garment, const Motion& motion,
                                                 int start, const std::vector<Eigen::MatrixXd>& posed_bodies,
                                                 double push_out_gap) {
  std::vector<Eigen::MatrixXd> targets;
  for (size_t k = 0; k < posed_bodies.size(); ++k)
    targets.push_back(lbs_garment(body, garment, motion, start + int(k), posed_bodies[k], push_out_gap));
  return targets;
}

int hold_pins_free_of_body(const Eigen::MatrixXi& garment_faces, const std::vector<int>& pinned,
                           const std::vector<Eigen::MatrixXd>& body, const Eigen::MatrixXi& body_faces,
                           std::vector<Eigen::MatrixXd>* pin_targets, Eigen::MatrixXd* x0, Eigen::MatrixXd* x_prev) {
  if (pinned.empty() || pin_targets->empty()) return 0;
  if (body.size() != pin_targets->size())
    throw Error("pins: " + std::to_string(pin_targets->size()) + " frames of pin targets for " +
                std::to_string(body.size()) + " body frames");
  const Eigen::MatrixXi edges = unique_edges(garment_faces);
  int most = 0;
  for (size_t k = 0; k < pin_targets->size(); ++k) {
    Eigen::MatrixXd& targets = (*pin_targets)[k];
    const Eigen::MatrixXd before = targets;
    most = std::max(most, push_pinned_edges_free_of_body(targets, pinned, edges, body[k], body_faces));
    if (k == 0)
      for (int i : pinned) {
        const Eigen::RowVector3d moved = targets.row(i) - before.row(i);
        x0->row(i) += moved;
        x_prev->row(i) += moved;
      }
  }
  return most;
}

int hold_pins_free_of_body(RolloutInput& in) {
  return hold_pins_free_of_body(in.garment_rest.F, in.pinned, in.body, in.body_faces, &in.pin_targets, &in.x0,
                                &in.x_prev);
}

namespace {

// The network's step with the model file's passes (contact projection, strain limit).
StepFunction network_with_passes(const ModelFile& model, const GarmentTopology& topology, int64_t k_override) {
  Pb4uNet net = model.model;
  const double gap = model.config.contact_projection, strain_limit = model.config.strain_limit;
  // The network (graph building included) runs where its weights are (--device); the
  // float64 physics state, metrics and the step constraints (strain limit, contact projection)
  // stay on the host.
  const torch::Device device = net->parameters().front().device();
  auto constrain = [gap, strain_limit, topology](const FrameState& state, torch::Tensor x_next,
                                                 const BodyContact* contact) {
    return constrain_step(x_next, state, contact, topology, strain_limit, gap);
  };
  if (device.is_cpu())
    return [net, topology, k_override, constrain](const FrameState& state, const ClothGeometry&, const TermList&,
                                                const BodyContact* contact) mutable {
      return constrain(state, net->step(state, topology, k_override).to(torch::kFloat64), contact);
    };
  GarmentTopology on_device = garment_topology_to(topology, device);
  return [net, on_device, device, k_override, constrain](const FrameState& state, const ClothGeometry&,
                                                       const TermList&, const BodyContact* contact) mutable {
    FrameState s = state;
    for (torch::Tensor* t : {&s.x, &s.x_prev, &s.pinned, &s.pin_targets, &s.body.vertices,
                             &s.body.next_vertices, &s.body.faces})
      if (t->defined()) *t = t->to(device);
    return constrain(state, net->step(s, on_device, k_override).to(torch::kCPU, torch::kFloat64), contact);
  };
}

}  // namespace

StepFunction network_stepper(const ModelFile& model, const GarmentTopology& topology, int64_t k_override,
                             std::shared_ptr<ContactStepLog> log, const ReferenceSolverConfig& base,
                             const RefineConfig& keys) {
  StepFunction step = network_with_passes(model, topology, k_override);
  if (!model.config.refines()) return step;
  RefineConfig refine = keys;
  refine.iterations = model.config.refine_iterations;
  refine.tolerance_mm = model.config.refine_tolerance_mm;
  ReferenceSolverConfig solver = base;  // as physics_measured_for measures it
  solver.contact = model.config.refine_contact;
  solver.strain_limit = model.config.refine_strain_limit;
  return refined_stepper(step, solver, refine, std::move(log));
}

PhysicsConfig physics_measured_for(const PhysicsConfig& physics, const ModelFile* model, bool refined_by_config) {
  PhysicsConfig measured = physics;
  if (model && !refined_by_config && model->config.refines()) {
    measured.solver.contact = model->config.refine_contact;
    measured.solver.strain_limit = model->config.refine_strain_limit;
  }
  return measured;
}

StepFunction reference_stepper(const ReferenceSolverConfig& solver, std::shared_ptr<ContactStepLog> log) {
  auto warned = std::make_shared<bool>(false);
  auto kappa = std::make_shared<double>(solver.barrier_stiffness);  // carried from step to step
  return [solver, warned, kappa, log](const FrameState& state, const ClothGeometry& cloth, const TermList& terms,
                                      const BodyContact* contact) {
    ReferenceSolverConfig config = solver;
    if (solver.barrier_stiffness_carries) config.barrier_stiffness = *kappa;
    const std::optional<BarrierStepInput> barrier = barrier_step_input(state, cloth, config);
    const SolverResult r = solve_reference_step(state, cloth, terms, contact, config, barrier ? &*barrier : nullptr);
    if (r.barrier_stiffness > 0) *kappa = r.barrier_stiffness;
    if (log) *log = {r.excluded, r.caught_by_body, r.body_lag, r.excluded_vertices, r.barrier_stiffness};
    if (r.excluded > 0) {
      // Said once per rollout at the default level, every frame with -v.
      const auto level = *warned ? spdlog::level::debug : spdlog::level::warn;
      const std::string caught =
          r.caught_by_body == 0 ? ""
          : r.body_lag > 0      ? fmt::format(" ({} caught by the body, placed {:.1f} mm short of its pose)",
                                              r.caught_by_body, 1e3 * r.body_lag)
                                : fmt::format(" ({} caught by the body as it moved)", r.caught_by_body);
      spdlog::log(level, "reference solver: {} cloth vertices found no intersection-free place{}: the penalty term "
                  "holds them{}",
                  r.excluded, caught, *warned ? "" : " (each such frame is logged with -v; energies.csv counts them)");
      *warned = true;
    }
    return r.x_next.to(torch::kFloat64);
  };
}

namespace {

// mm: how close to its minimum the solve from a sampled frame's step goes (minimum_every).
constexpr double kMinimumToleranceMm = 1e-3;

bool report_finite(const EnergyReport& r) {
  if (!std::isfinite(r.total)) return false;
  for (const auto& t : r.terms)
    if (!std::isfinite(t.second)) return false;
  return true;
}

// The vertex that moved most from x to x_next, a non-finite one first.
int worst_vertex(const torch::Tensor& x, const torch::Tensor& x_next) {
  auto d = (x_next - x).norm(2, 1);
  d = torch::where(torch::isfinite(d), d, torch::full_like(d, INFINITY));
  return static_cast<int>(d.argmax().item<int64_t>());
}

}  // namespace

FrameState rollout_start_state(const RolloutInput& in) {
  const int64_t n = in.garment_rest.V.rows();
  if (in.x0.rows() != n || in.x_prev.rows() != n || in.x0.cols() != 3 || in.x_prev.cols() != 3)
    throw Error("rollout: initial garment state does not match the rest mesh's " + std::to_string(n) + " vertices");
  if (in.effects.needs_body() && int(in.body.size()) < std::max(in.steps + 1, 1))
    throw Error("rollout: the effects need a body but " + std::to_string(in.body.size()) +
                " body frames were given for " + std::to_string(in.steps) + " steps");
  if (!in.body.empty() && int(in.body.size()) < in.steps + 1)
    throw Error("rollout: " + std::to_string(in.body.size()) + " body frames were given for " +
                std::to_string(in.steps) + " steps (it needs frames 0.." + std::to_string(in.steps) + ")");
  FrameState state;
  state.x = matrix_to_tensor(in.x0);
  state.x_prev = matrix_to_tensor(in.x_prev);
  state.effects = in.effects;
  state.material = in.material;
  state.dt = in.dt;
  if (in.effects.pins && !in.pinned.empty()) {
    state.pinned = torch::zeros({n}, torch::kBool);
    for (int i : in.pinned) {
      if (i < 0 || i >= n) throw Error("rollout: pinned vertex " + std::to_string(i) + " out of range");
      state.pinned[i] = true;
    }
    if (in.pin_targets.empty()) {
      state.pin_targets = state.x.clone();
    } else {
      if (int(in.pin_targets.size()) < in.steps + 1)
        throw Error("rollout: " + std::to_string(in.pin_targets.size()) + " frames of pin targets were given for " +
                    std::to_string(in.steps) + " steps (it needs frames 0.." + std::to_string(in.steps) + ")");
      for (const auto& p : in.pin_targets)
        if (p.rows() != n || p.cols() != 3)
          throw Error("rollout: pin targets do not match the rest mesh's " + std::to_string(n) + " vertices");
      state.pin_targets = matrix_to_tensor(in.pin_targets[std::min(1, in.steps)]);
    }
  }
  if (in.effects.needs_body()) {
    state.body.vertices = matrix_to_tensor(in.body[0]);
    state.body.next_vertices = matrix_to_tensor(in.body[std::min<size_t>(1, in.body.size() - 1)]);
    state.body.faces = index_matrix_to_tensor(in.body_faces);
  }
  return state;
}

RolloutResult run_rollout(const RolloutInput& in, const StepFunction& step,
                          const PhysicsConfig& physics, const FrameCallback& on_frame) {
  FrameState state = rollout_start_state(in);
  const bool with_body = in.effects.needs_body();
  ClothGeometry cloth = make_cloth_geometry(in.garment_rest, torch::kFloat64, torch::kCPU, false,
                                            physics.degenerate_area);
  TermList terms = build_terms(in.effects, physics);

  const bool measure_penetration = !in.body.empty();
  // Edges of the garment and of the body, for the edges through the body each frame: the
  // topology is the rollout's, only the body's positions change.
  const Eigen::MatrixXi garment_edges = measure_penetration ? unique_edges(in.garment_rest.F) : Eigen::MatrixXi();
  ContactSurface posed_body;
  if (measure_penetration) posed_body = make_contact_surface(in.body[0], in.body_faces);
  RolloutResult result;
  const ResidualHessian residual_hessian = residual_hessian_from_name(physics.solver.residual_hessian);
  double start_positive = 0;  // frame 1's positive energy (J): the divergence guard's start
  for (int frame = 1; frame <= in.steps; ++frame) {
    if (with_body && frame > 1) {
      state.body.vertices = matrix_to_tensor(in.body[frame - 1]);
      state.body.next_vertices = matrix_to_tensor(in.body[frame]);
    }
    if (state.pinned.defined() && !in.pin_targets.empty() && frame > 1)
      state.pin_targets = matrix_to_tensor(in.pin_targets[frame]);
    auto t0 = std::chrono::steady_clock::now();
    std::optional<BodyContact> contact = body_contact_for(state, physics);
    const double contact_ms = ms_since(t0);
    t0 = std::chrono::steady_clock::now();
    torch::Tensor x_next = step(state, cloth, terms, contact ? &*contact : nullptr);
    const double step_ms = ms_since(t0);
    bool finite = torch::isfinite(x_next).all().item<bool>();
    EnergyReport report;
    if (finite) {
      report = energy_report(terms, x_next, state, cloth, contact ? &*contact : nullptr, in.metric_material);
      finite = report_finite(report);
      if (finite && in.measure_residual) {
        FrameState measured = state;
        measured.material = in.metric_material;
        // With barrier contact, the distance to the intersection-free solver's minimum.
        std::optional<BarrierStepInput> barrier = barrier_step_input(state, cloth, physics.solver);
        // Where this step was a barrier solve, the solver's own objective: its kappa and the
        // vertices it left out.
        const bool solved = barrier && in.step_log && in.step_log->barrier_stiffness > 0;
        if (solved) barrier->settings.stiffness = in.step_log->barrier_stiffness;
        report.residual_mm = 1e3 * step_residual(x_next, measured, cloth, terms, contact ? &*contact : nullptr,
                                                 barrier ? &*barrier : nullptr,
                                                 solved ? &in.step_log->excluded_vertices : nullptr,
                                                 residual_hessian);
      }
    }
    if (finite && in.minimum_every > 0 && frame % in.minimum_every == 0) {
      FrameState measured = state;
      measured.material = in.metric_material;
      RefineConfig to_minimum;
      to_minimum.tolerance_mm = kMinimumToleranceMm;
      // From the step where it stands (made free of the body at t + dt), never from the
      // solver's own start: the minimum nearest the step, not another one.
      ReferenceSolverConfig from_step = physics.solver;
      from_step.given_start = "at_step";
      from_step.own_start_where_left_out = false;
      const torch::Tensor at_step = x_next.to(torch::kFloat64);
      const torch::Tensor x_min =
          refine_step(at_step, measured, cloth, terms, contact ? &*contact : nullptr, from_step, to_minimum);
      report.minimum_distance_mm = 1e3 * (x_min - at_step).pow(2).sum(1).sqrt().max().item<double>();
      report.minimum_gap_j =
          report.total -
          energy_report(terms, x_min, state, cloth, contact ? &*contact : nullptr, in.metric_material).total;
    }
    if (!finite) {
      result.diverged = true;
      result.diverged_at_frame = frame;
      result.diverged_reason = "non-finite position or energy";
      result.worst_vertex = worst_vertex(state.x, x_next);
      break;
    }
    const Eigen::MatrixXd x = tensor_to_matrix(x_next);
    std::optional<PenetrationFigures> penetration;
    if (measure_penetration) {
      penetration = garment_penetration(x, in.body[frame], in.body_faces);
      posed_body.V = in.body[frame];
      penetration->edges_through = int(cloth_edges_through_body(x, garment_edges, posed_body).size());
      result.penetration.push_back(*penetration);
    }
    result.reports.push_back(report);
    result.step_ms.push_back(step_ms);
    if (in.step_log && in.step_log->own_start) ++result.own_start_frames;
    result.contact_ms.push_back(contact_ms);
    if (on_frame) on_frame(frame, x, report, penetration ? &*penetration : nullptr);
    const double positive = positive_energy(report);
    if (frame == 1) start_positive = positive;
    std::string why = energy_divergence(in.divergence, start_positive, positive);
    if (!why.empty()) {
      // Where the body crosses itself, cloth pinched between its parts has nowhere to go: say so.
      if (penetration && penetration->body_self_crossing_faces > 0)
        why += ", on a frame where the body crosses itself (" + std::to_string(penetration->body_self_crossing_faces) +
               " of its faces inside another part)";
      result.diverged = true;
      result.diverged_at_frame = frame;
      result.diverged_reason = why;
      result.worst_vertex = worst_vertex(state.x, x_next);
      break;
    }
    state.x_prev = state.x;
    state.x = x_next;
  }
  return result;
}

}  // namespace pb4u

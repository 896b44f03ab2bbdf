#include "pb4u/rollout/settled_start.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <utility>

#include <spdlog/fmt/fmt.h>

#include "pb4u/body/forward_kinematics.h"
#include "pb4u/body/linear_blend_skinning.h"
#include "pb4u/physics/penetration.h"
#include "pb4u/rollout/rollout.h"
#include "pb4u/util/error.h"

namespace pb4u {

SettledStart settled_start(const Body& body, const Garment& garment, const Pose& first, const Pose& next, int steps,
                           const Material& material, const std::vector<int>& pinned, double push_out_gap,
                           const PhysicsConfig& physics) {
  if (garment.weights.rows() != garment.mesh.V.rows())
    throw Error("settled start: garment '" + garment.name + "' has no skinning weights");
  if (steps < 1) throw Error("settled start: steps must be at least 1");
  const auto t0 = std::chrono::steady_clock::now();
  Motion path;
  for (int k = 0; k <= steps; ++k) path.frames.push_back(blend_poses(body.bind, first, double(k) / steps));
  auto skin = [&](const Pose& p) {
    return linear_blend_skinning(garment.mesh.V, garment.weights, skinning_transforms(body.skeleton, body.bind, p));
  };
  std::vector<Eigen::MatrixXd> bodies, skinned;
  for (const Pose& p : path.frames) {
    bodies.push_back(pose_body(body, p));
    skinned.push_back(skin(p));
  }
  // Barrier contact whatever the scene's solver: the steps exist to keep the cloth out of the body.
  PhysicsConfig barrier = physics;
  barrier.solver.contact = "barrier";
  RolloutInput in;
  in.garment_rest = garment.mesh;
  in.effects = Effects::from_names({"collision"}, "settled start");
  in.material = in.metric_material = material;
  in.steps = 1;
  in.measure_residual = false;
  in.body_faces = body.mesh.F;
  std::vector<Eigen::MatrixXd> pin_targets;
  if (!pinned.empty()) {
    in.effects.pins = true;
    in.pinned = pinned;
    pin_targets = skinned_pin_targets(body, garment, path, 0, bodies, push_out_gap);
    Eigen::MatrixXd unused_x0 = garment.mesh.V, unused_prev = garment.mesh.V;
    hold_pins_free_of_body(garment.mesh.F, pinned, bodies, body.mesh.F, &pin_targets, &unused_x0, &unused_prev);
  }
  SettledStart out;
  out.x = garment.mesh.V;
  for (int i : pinned) out.x.row(i) = pin_targets[0].row(i);
  // Step k of the path from out.x, with the solver's release of held cloth on or off.
  struct Step {
    Eigen::MatrixXd x;
    int edges_through = 0, excluded = 0;
    double inside_fraction = 0;
    bool leaves_nothing_out() const { return edges_through == 0 && excluded == 0 && inside_fraction == 0; }
    bool better_than(const Step& o) const {
      if (edges_through != o.edges_through) return edges_through < o.edges_through;
      if (inside_fraction != o.inside_fraction) return inside_fraction < o.inside_fraction;
      return excluded < o.excluded;
    }
  };
  auto step = [&](int k, bool release) {
    in.x0 = out.x;
    in.x_prev = out.x - (skinned[size_t(k + 1)] - skinned[size_t(k)]);
    in.body = {bodies[size_t(k)], bodies[size_t(k + 1)]};
    if (!pinned.empty()) in.pin_targets = {pin_targets[size_t(k)], pin_targets[size_t(k + 1)]};
    PhysicsConfig p = barrier;
    p.solver.release_held_cloth = release;
    auto log = std::make_shared<ContactStepLog>();
    Step st;
    const RolloutResult r = run_rollout(in, reference_stepper(p.solver, log), p,
                                        [&](int, const Eigen::MatrixXd& x, const EnergyReport&,
                                            const PenetrationFigures* pen) {
                                          st.x = x;
                                          if (pen) st.edges_through = pen->edges_through, st.inside_fraction = pen->penetrating_fraction;
                                        });
    if (r.diverged) throw Error("settled start: step " + std::to_string(k + 1) + " of " + std::to_string(steps) + ": " + r.diverged_reason);
    st.excluded = log->excluded;
    return st;
  };
  // Each step first with the body carrying the cloth it meets (release_held_cloth off), and
  // where that leaves cloth through the body or out of barrier contact, again with the cloth that
  // holds the body's move released: whichever leaves fewer edges through, then fewer vertices
  // inside, is kept. Neither is best everywhere: on the tiny jump's crouch the release leaves 10
  // edges through and carrying none; on the CMU demo walk, whose hand rests in the belly,
  // carrying ends with 49 and the release with 6 (docs/physics.md, "A skinned first frame").
  for (int k = 0; k < steps; ++k) {
    Step kept = step(k, false);
    if (!kept.leaves_nothing_out()) {
      Step released = step(k, true);
      if (released.better_than(kept)) kept = std::move(released);
    }
    out.x = kept.x;
    out.edges_through = kept.edges_through;
    out.inside_fraction = kept.inside_fraction;
    out.excluded_max = std::max(out.excluded_max, kept.excluded);
  }
  // The body is already moving at the first pose: the cloth moves as skinning would move it.
  out.x_prev = out.x - (skin(next) - skinned.back());
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

void settled_rollout_start(const SettledStart& st, const std::vector<int>& riding, const Eigen::MatrixXd& pin_targets,
                           Eigen::MatrixXd* x0, Eigen::MatrixXd* x_prev) {
  *x0 = st.x;
  for (int v : riding) x0->row(v) = pin_targets.row(v);
  *x_prev = *x0 - (st.x - st.x_prev);
}

std::string describe_settled_start(const SettledStart& st, int steps) {
  return fmt::format("start settled from the bind pose in {} solver steps ({:.1f} s): {} cloth edges through the body, "
                     "{:.2f}% of the vertices inside it; at most {} vertices a step out of barrier contact",
                     steps, st.seconds, st.edges_through, 100 * st.inside_fraction, st.excluded_max);
}

}  // namespace pb4u

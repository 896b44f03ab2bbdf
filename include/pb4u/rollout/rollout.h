#pragma once
// A rollout: a garment advanced frame by frame by a stepper (the network or the reference
// solver) on a prescribed body motion, each frame's active terms measured. Shared by
// `evaluate` (Table 1) and `simulate`. The physics state is float64; the network steps in its
// own dtype.
#include <torch/torch.h>

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "pb4u/body/body.h"
#include "pb4u/rollout/divergence_guard.h"
#include "pb4u/rollout/refine_config.h"
#include "pb4u/model/model_file.h"
#include "pb4u/garment/garment.h"
#include "pb4u/graph/garment_topology.h"
#include "pb4u/physics/body_queries.h"
#include "pb4u/physics/energy_report.h"
#include "pb4u/physics/penetration.h"
#include "pb4u/physics/physics_term.h"
#include "pb4u/scene/effects.h"
#include "pb4u/util/eigen_tensor.h"

namespace pb4u {

struct ContactStepLog;

struct RolloutInput {
  TriMesh garment_rest;              // rest shape (m): cloth geometry, topology, Lbar
  Eigen::MatrixXd x0, x_prev;        // n x 3 m: garment at frame 0 and one frame before
  // nb x 3 m per frame, frames 0..steps; empty: no body. With a body every frame's garment is
  // also measured against it (penetration).
  std::vector<Eigen::MatrixXd> body;
  Eigen::MatrixXi body_faces;        // mb x 3, outward
  std::vector<int> pinned;           // pinned vertex indices, held at their x0 positions...
  // ...or, when given, moved to these positions: n x 3 m per frame, frames 0..steps (pins riding
  // on a body: skinned_pin_targets).
  std::vector<Eigen::MatrixXd> pin_targets;
  Effects effects;
  Material material;                 // what the cloth is made of (network input, solver)
  Material metric_material;          // what the energies are reported under
  int steps = 0;                     // frames to advance
  double dt = 1.0 / 30.0;            // s
  DivergenceConfig divergence;       // when to stop beyond non-finite values
  bool measure_residual = true;      // each frame's EnergyReport::residual_mm (step_residual.h)
  // > 0: every minimum_every-th frame, the step solved to the minimum from where it stands
  // (EnergyReport::minimum_distance_mm, minimum_gap_j): a reference solve a sampled frame.
  int minimum_every = 0;
  // The step's ContactStepLog, when its stepper writes one: the residual then measures the
  // solver's objective (its left-out vertices and kappa) instead of recomputing who is free.
  std::shared_ptr<const ContactStepLog> step_log;
};

// The rollout of `garment` worn by `body` under `motion`, from its LBS-initialised frame
// `start` (pushed `push_out_gap` m out of the body) for `steps` frames; body frames are posed
// only when the effects need a body. Material and metric material are both `material`.
RolloutInput lbs_rollout_input(const Body& body, const Garment& garment, const Motion& motion, int start,
                               int steps, const Effects& effects, const Material& material,
                               double push_out_gap);

// The targets of pins that ride on the body (a waistband held on): per posed body frame k (the
// body at motion frame start + k, as RolloutInput::body holds it), the garment skinned to that
// frame and pushed `push_out_gap` m out of it (data/lbs_frame.h).
std::vector<Eigen::MatrixXd> skinned_pin_targets(const Body& body, const Garment& garment, const Motion& motion,
                                                 int start, const std::vector<Eigen::MatrixXd>& posed_bodies,
                                                 double push_out_gap);

// Pins held where no edge between two pinned vertices cuts the body, on every frame
// (physics/intersection_free_start.h: push_pinned_edges_free_of_body): each frame's pin targets
// (one per posed body frame, garment-sized), and the start state with them: x0's pinned rows
// move as frame 0's targets did, and x_prev's as far, so the pins start at rest relative to the
// body. Returns the most edges a frame still has through the body (0 when all cleared).
int hold_pins_free_of_body(const Eigen::MatrixXi& garment_faces, const std::vector<int>& pinned,
                           const std::vector<Eigen::MatrixXd>& body, const Eigen::MatrixXi& body_faces,
                           std::vector<Eigen::MatrixXd>* pin_targets, Eigen::MatrixXd* x0, Eigen::MatrixXd* x_prev);
// The same on a rollout's input (its garment, pins, body and start).
int hold_pins_free_of_body(RolloutInput& in);

// Advances one frame: float64 state in, float64 x_{t+1} (n, 3) out.
using StepFunction = std::function<torch::Tensor(const FrameState& state, const ClothGeometry& cloth,
                                                 const TermList& terms, const BodyContact* contact)>;

// What the reference solver's intersection-free contact did in the last step (solver.contact =
// barrier with a body; zeros otherwise): the vertices it left out of barrier contact, those of
// them the body caught, and how far the body was from its pose when it was placed there (m).
// The residual of such a step is measured with the solver's own objective: its left-out
// vertices (per cloth vertex, empty: none) and the barrier stiffness it ended with (J/m^2; 0:
// not a barrier solve).
struct ContactStepLog {
  int excluded = 0, caught_by_body = 0;
  double body_lag = 0;
  std::vector<char> excluded_vertices;
  double barrier_stiffness = 0;
  // A refinement that started from the solver's own start: without barrier contact where the
  // network's step was higher in the solver's objective, with it where the step left cloth with
  // no free place and solver.own_start_where_left_out is on (SolverResult::own_start).
  bool own_start = false;
};

// The network's step: K from its calibration and the garment's Lbar, or `k_override` if >= 0.
// With the file's own refinement (refine_iterations, refine_tolerance_mm), the refining solver
// is `solver` (the scene's or config's physics.solver) with the file's refine_contact and
// refine_strain_limit, refining as `refine` says but for the count and the tolerance, which
// are the file's (its step and release_held_cloth: the scene's or config's refine section);
// `log`, when given, is overwritten by each refining solve.
StepFunction network_stepper(const ModelFile& model, const GarmentTopology& topology, int64_t k_override = -1,
                             std::shared_ptr<ContactStepLog> log = nullptr,
                             const ReferenceSolverConfig& solver = ReferenceSolverConfig(),
                             const RefineConfig& refine = RefineConfig());

// The physics a rollout of `model` (null: the solver) is measured with: `physics`, but where the
// model file refines its own steps (ModelConfig::refines()) and `refined_by_config` does not
// override that, the solver keys its refinement uses (refine_contact, refine_strain_limit), so
// that the residual is measured on the objective the refinement minimises.
PhysicsConfig physics_measured_for(const PhysicsConfig& physics, const ModelFile* model, bool refined_by_config);

// The reference solver's step (SPEC 8); `log`, when given, is overwritten by each step.
StepFunction reference_stepper(const ReferenceSolverConfig& solver,
                               std::shared_ptr<ContactStepLog> log = nullptr);

struct RolloutResult {
  // One per measured frame 1..: every finite frame up to the stop, the frame whose positive
  // energy tripped the guard included (it is finite: its figures show the blow-up).
  std::vector<EnergyReport> reports;
  // With a body, one per report: x_{t+1} against the body at t + 1. Empty without a body.
  std::vector<PenetrationFigures> penetration;
  bool diverged = false;
  int diverged_at_frame = -1;         // the frame that stopped the rollout
  std::string diverged_reason;        // "non-finite position or energy" or the energy guard's reason
  int worst_vertex = -1;              // the vertex that moved most (non-finite first) there
  // Wall time (ms) per finite frame of the stepper and of the body contact query
  // (body_contact_for: KD-tree and closest points, which the physics terms and the solver use).
  std::vector<double> step_ms, contact_ms;
  // Frames whose refinement started from the solver's own start (ContactStepLog::own_start).
  int own_start_frames = 0;
};

// Called with frame index (1..steps), garment positions (n x 3 m), the frame's energies and,
// with a body, its penetration (null without one).
using FrameCallback = std::function<void(int frame, const Eigen::MatrixXd& garment, const EnergyReport& report,
                                         const PenetrationFigures* penetration)>;

// Frame 0 of the rollout as the stepper sees it: positions, effects, material, pins and, when
// the effects need a body, the body at frames 0 and 1. Throws pb4u::Error on inconsistent input.
FrameState rollout_start_state(const RolloutInput& input);

// Runs the rollout; a non-finite frame, or one whose positive energy trips
// input.divergence, stops it (reported, never thrown). Throws pb4u::Error on inconsistent
// input (sizes, a body missing when the effects need one).
RolloutResult run_rollout(const RolloutInput& input, const StepFunction& step,
                          const PhysicsConfig& physics, const FrameCallback& on_frame = {});

}  // namespace pb4u

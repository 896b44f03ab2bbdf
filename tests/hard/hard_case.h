#pragma once
// Shared pieces of the hard-case suite (issues 9, 14, 33): models, meshes that are hard on
// purpose, one check that a rollout stays finite and bounded frame by frame, the SPEC 9 check
// that a network stays bounded against the reference solver on the same scene, and the shipped
// network run three ways against it (alone, with its inference passes, refined by the solver).
#include <optional>
#include <string>

#include "pb4u/graph/garment_topology.h"
#include "pb4u/model/model_file.h"
#include "pb4u/model/pass_variants.h"
#include "pb4u/rollout/refined_step.h"
#include "pb4u/rollout/rollout.h"

namespace pb4u::hard {

// Size multiplier for meshes and frame counts: 1 in ctest, larger from scripts/hard_cases.sh
// (environment PB4U_HARD_SCALE).
int scale();

// How the body cases reach their first frame (SceneBody::start): "skinned" in ctest, "settled"
// from scripts/hard_cases.sh --start settled (environment PB4U_HARD_START).
std::string body_start();

// `physics` with the physics.solver keys of scripts/hard_cases.sh --step / --solver (environment
// PB4U_HARD_SOLVER_STEP, PB4U_HARD_SOLVER), checked as a config file's are.
PhysicsConfig with_solver_overrides(const PhysicsConfig& physics);
// `refine` with scripts/hard_cases.sh --refine's keys (PB4U_HARD_REFINE) but its count and tolerance.
RefineConfig with_refine_overrides(const RefineConfig& refine);

// The shipped model (data/pretrained/pb4u.h5), loaded once.
const ModelFile& shipped_model();
// A small randomly initialised Pb4U-GNet (fixed seed), calibrated to `lbar_base` (m), in
// eval mode with empty normalisers (identity): what an untrained network does on its own.
ModelFile untrained_model(double lbar_base);

// A closed, outward-oriented axis-aligned box (12 triangles) of half-size h centred at c.
void box_mesh(const Eigen::Vector3d& c, double h, Eigen::MatrixXd* V, Eigen::MatrixXi* F);

// A rollout of `garment` at rest, starting still, with the given effects and the top row
// (vertices with y within 1e-6 of the highest) pinned when effects.pins.
RolloutInput still_start(const TriMesh& garment, const Effects& effects, const Material& material, int steps);

// Whether a check fails the test (gtest EXPECTs) or only reports its verdict in the printed
// lines: the network alone and with its heuristic passes are measured against the same bounds
// as the refined network, which is the one judged.
enum class Judge { kExpect, kReport };

struct Bounds {
  double max_stretch = 3.0;  // largest allowed current / rest edge length; <= 0: not checked
  // Edges only in faces of zero rest area are left out: nothing resists their stretch.
  bool skip_zero_area_edges = true;
  double max_speed = 0;  // m/s, fastest allowed garment vertex; <= 0: not checked
  // false: only a non-finite frame stops the rollout (finiteness-only checks, where the
  // energy may grow without bound by design: random weights).
  bool energy_guard = true;
  // Every frame free of the body: no cloth vertex inside it, no cloth edge through a body
  // triangle (the intersection-free solver's promise; with a body only).
  bool intersection_free = false;
};

// Bounds with only finiteness checked.
Bounds finite_only();

struct RolloutFigures {
  int frames = 0;
  double max_stretch = 0;      // largest current / rest edge length seen
  double max_total = 0;        // J, largest total energy of a frame
  double max_speed = 0;        // m/s, fastest garment vertex
  double mean_positive = 0;    // J, stretch + bending + collision, mean per frame
  double max_positive = 0;     // J, its largest frame
  std::optional<PenetrationSummary> penetration;  // with a body
  double seconds = 0;
  int violations = 0;              // frames and checks outside the bounds (Judge::kReport)
  std::string first_violation;     // what the first one was
};

// Runs the rollout and checks every frame: positions and every energy finite, the non-negative
// terms (all but gravity) >= 0, no divergence (non-finite, or the input's energy guard unless
// bounds.energy_guard is off), every frame produced, edges within bounds, and where asked the
// frame free of the body. Judge::kExpect: each miss is a gtest failure; kReport: they are
// counted and the first is printed. Prints one "[hard] <label>: ..." line with the figures.
RolloutFigures check_rollout(const std::string& label, const RolloutInput& input, const StepFunction& step,
                             const PhysicsConfig& physics, const Bounds& bounds = {}, Judge judge = Judge::kExpect);

// SPEC 9: a network is stable when it stays bounded against the reference solver on the same
// scene, not merely finite. Energies are divided by the reference's with no floor: a ratio over
// the bound fails however small both energies are. Only a reference at rest to rounding (its
// positive energy under kReferenceAtRest) leaves the ratio undefined; the case's strain and
// penetration bounds, in physical units, judge it then.
struct RelativeBounds {
  double mean_positive_ratio = 10;       // network mean positive energy / reference's
  double max_positive_ratio = 10;        // network largest frame / reference's largest
  double penetrating_fraction_margin = 0.05;  // network mean share inside <= reference's + this
  double penetration_mm_margin = 10;     // network deepest penetration (mm) <= reference's + this
};

// J: a positive energy this small is rounding (a cloth at its rest shape reads 0 to ~1e-15 J).
constexpr double kReferenceAtRest = 1e-12;

// Checks `network` against `reference`, both run on the same input, and prints one
// "[hard] <label>: ..." line with the ratios and margins. Returns whether every bound holds;
// Judge::kExpect also makes each miss a gtest failure.
bool check_relative(const std::string& label, const RolloutFigures& network, const RolloutFigures& reference,
                    const RelativeBounds& bounds = {}, Judge judge = Judge::kExpect);

// The solver the network is held against: `physics` with the intersection-free contact
// (solver.contact = barrier) where the input has a body to collide with.
PhysicsConfig reference_physics(const PhysicsConfig& physics, const RolloutInput& in);

// The reference solver's rollout on `in` (reference_physics), checked with `bounds` and, with a
// body, intersection-free on every frame.
RolloutFigures check_reference(const std::string& label, const RolloutInput& in, const PhysicsConfig& physics,
                               Bounds bounds = {});

// The refinements: each network step refined by kRefineIterations solver iterations (judged
// until 2026-11-26, now reported), and the judged one, those iterations and then on until the
// solver's step is below kRefineToleranceMm (a tolerance alone stops at once on a slow cloth
// whose step is already within it). Both fixed before measuring; the refinement Table 1's
// `refined` rows report (model/pass_variants.h).
constexpr int kRefineIterations = kTableRefineIterations;
constexpr double kRefineToleranceMm = kTableRefineToleranceMm;

struct ShippedFigures {
  RolloutFigures alone, passes, refined_fixed, refined;
};

// The shipped network on `in` three ways, each held against `reference` (check_relative):
//  - alone: the model file without its inference passes (contact projection, strain limit);
//  - with its passes: the shipped file as it is;
//  - refined by kRefineIterations iterations of the reference solver (reference_physics);
//  - refined: by those iterations, then on until the solver's step is below
//    kRefineToleranceMm, intersection-free on every frame where there is a body.
// The last is judged (gtest EXPECTs, `bounds` and `relative`); the other three are reported
// against the same bounds, with a verdict line each.
ShippedFigures check_shipped(const std::string& label, const RolloutInput& in, const GarmentTopology& topology,
                             const PhysicsConfig& physics, const RolloutFigures& reference, const Bounds& bounds,
                             const RelativeBounds& relative = {});

}  // namespace pb4u::hard

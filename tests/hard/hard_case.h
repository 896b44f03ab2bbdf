#pragma once
// Shared pieces of the hard-case suite (issues 9, 14): models, meshes that are hard on purpose,
// one check that a rollout stays finite and bounded frame by frame, and the SPEC 9 check
// that a network stays bounded against the reference solver on the same scene.
#include <optional>
#include <string>

#include "pb4u/model/model_file.h"
#include "pb4u/rollout/rollout.h"

namespace pb4u::hard {

// Size multiplier for meshes and frame counts: 1 in ctest, larger from scripts/hard_cases.sh
// (environment PB4U_HARD_SCALE).
int scale();

// The shipped model (data/pretrained/pb4u.h5), loaded once.
const ModelFile& shipped_model();
// A small randomly initialised Pb4U-GNet (fixed seed), calibrated to `lbar_base` (m), in
// eval mode with empty normalisers (identity): what an untrained network does on its own.
ModelFile untrained_model(double lbar_base);

// A res_x x res_y cloth hanging in the xy plane (top row at y = 1 m, rows dy apart, odd rows
// shifted by dx / 2, so every edge is at least dx / 2 long), faces oriented +z. Row
// `thin_row`'s strip (between it and the next row) is squeezed to height `thin_height` (m):
// 1e-8 makes sliver triangles of area ~ dx * 1e-8 / 2, 0 zero-area ones. thin_row < 0: none.
TriMesh lattice_cloth(int res_x, int res_y, double dx, int thin_row = -1, double thin_height = 0.0);

// A closed, outward-oriented axis-aligned box (12 triangles) of half-size h centred at c.
void box_mesh(const Eigen::Vector3d& c, double h, Eigen::MatrixXd* V, Eigen::MatrixXi* F);

// A rollout of `garment` at rest, starting still, with the given effects and the top row
// (vertices with y within 1e-6 of the highest) pinned when effects.pins.
RolloutInput still_start(const TriMesh& garment, const Effects& effects, const Material& material, int steps);

struct Bounds {
  double max_stretch = 3.0;  // largest allowed current / rest edge length; <= 0: not checked
  // Edges only in faces of zero rest area are left out: nothing resists their stretch.
  bool skip_zero_area_edges = true;
  double max_speed = 0;  // m/s, fastest allowed garment vertex; <= 0: not checked
  // false: only a non-finite frame stops the rollout (finiteness-only checks, where the
  // energy may grow without bound by design: random weights).
  bool energy_guard = true;
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
};

// Runs the rollout and checks (gtest EXPECTs) every frame: positions and every energy
// finite, the non-negative terms (all but gravity) >= 0, no divergence (non-finite, or the
// input's energy guard unless bounds.energy_guard is off), every frame produced, edges within
// bounds. Prints one "[hard] <label>: ..." line with the figures.
RolloutFigures check_rollout(const std::string& label, const RolloutInput& input, const StepFunction& step,
                             const PhysicsConfig& physics, const Bounds& bounds = {});

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

// Checks (gtest EXPECTs) `network` against `reference`, both run on `input`, and prints one
// "[hard] <label>: ..." line with the ratios and margins.
void check_relative(const std::string& label, const RolloutFigures& network, const RolloutFigures& reference,
                    const RelativeBounds& bounds = {});

}  // namespace pb4u::hard

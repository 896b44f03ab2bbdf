#pragma once
// Per-frame energies of the active terms and their sum: the metric behind `evaluate`
// (Table 1 rows) and the training loss.
#include <torch/torch.h>

#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "pb4u/physics/physics_term.h"

namespace pb4u {

struct EnergyReport {
  std::vector<std::pair<std::string, double>> terms;  // active terms, Table-1 order, J
  double total = 0;                                   // J
  // mm: how far the step is from the minimum of this energy (step_residual.h); NaN where not
  // measured. Not a term: it is in neither `terms` nor `total`.
  double residual_mm = std::numeric_limits<double>::quiet_NaN();
  // On sampled frames (RolloutInput::minimum_every), the step against the minimum the reference
  // solver reaches from it (to 0.001 mm; a refinement's solve from the step where it stands,
  // made free of the body first, at the barrier's fixed kappa): the largest vertex move there
  // (mm) and how much lower this energy's total is there (J; below 0 where the barrier the
  // solve minimises with it costs more than the terms gain). NaN where not measured.
  double minimum_distance_mm = std::numeric_limits<double>::quiet_NaN();
  double minimum_gap_j = std::numeric_limits<double>::quiet_NaN();

  bool has(const std::string& name) const;
  double value(const std::string& name) const;  // throws pb4u::Error when absent
};

// Each term's energy tensor (0-dim, differentiable in x_next) in the order of `terms`.
std::vector<std::pair<std::string, torch::Tensor>> term_energies(
    const TermList& terms, const torch::Tensor& x_next, const FrameState& state,
    const ClothGeometry& cloth, const BodyContact* contact);

// Their sum (J): the training loss / the solver's objective.
torch::Tensor total_energy(const TermList& terms, const torch::Tensor& x_next,
                           const FrameState& state, const ClothGeometry& cloth,
                           const BodyContact* contact);

// The frame's report under `material` (default: the evaluation material, SPEC 2), whatever
// material the state carries. No gradients are recorded.
EnergyReport energy_report(const TermList& terms, const torch::Tensor& x_next,
                           const FrameState& state, const ClothGeometry& cloth,
                           const BodyContact* contact, const Material& material = Material{});

// Term-wise mean over frames (SPEC 3: reported per frame, averaged over a sequence). All
// reports must list the same terms; throws pb4u::Error otherwise or when empty.
EnergyReport mean_report(const std::vector<EnergyReport>& reports);

// Positive energy (J): stretch + bending + collision (+ repulsion), those the report has. SPEC 9's
// stability figure: the terms that grow without bound when a rollout blows up (gravity and
// inertia do not measure a broken cloth).
double positive_energy(const EnergyReport& report);
// Positive energy over a sequence of frames: mean per frame and largest frame (both 0 when
// there are no frames).
struct PositiveEnergyRange {
  double mean = 0, max = 0;
};
PositiveEnergyRange positive_energy_range(const std::vector<EnergyReport>& reports);
// mm: the step's residual (EnergyReport::residual_mm) of the frames where it was measured, and
// their median (NaN where none was).
std::vector<double> measured_residuals_mm(const std::vector<EnergyReport>& reports);
double median_residual_mm(const std::vector<EnergyReport>& reports);
// The frames sampled for their minimum (EnergyReport::minimum_distance_mm and minimum_gap_j):
// how many, the median and largest distance (mm) and the median energy gap (J) over them; NaN
// where no frame was sampled.
struct MinimumSummary {
  int frames = 0;
  double distance_median_mm = std::numeric_limits<double>::quiet_NaN();
  double distance_max_mm = std::numeric_limits<double>::quiet_NaN();
  double gap_median_j = std::numeric_limits<double>::quiet_NaN();
};
MinimumSummary summarize_minimum(const std::vector<EnergyReport>& reports);
// Whether the term called `name` counts towards the positive energy.
bool is_positive_term(const std::string& name);

}  // namespace pb4u

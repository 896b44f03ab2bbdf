#include "pb4u/physics/energy_report.h"

#include <algorithm>
#include <cmath>

#include "pb4u/util/error.h"
#include "pb4u/util/median.h"

namespace pb4u {

bool EnergyReport::has(const std::string& name) const {
  for (const auto& t : terms)
    if (t.first == name) return true;
  return false;
}

double EnergyReport::value(const std::string& name) const {
  for (const auto& t : terms)
    if (t.first == name) return t.second;
  throw Error("energy report: no term '" + name + "' (the scene does not have that effect)");
}

std::vector<std::pair<std::string, torch::Tensor>> term_energies(
    const TermList& terms, const torch::Tensor& x_next, const FrameState& state,
    const ClothGeometry& cloth, const BodyContact* contact) {
  std::vector<std::pair<std::string, torch::Tensor>> out;
  out.reserve(terms.size());
  for (const auto& t : terms) out.emplace_back(t->name(), t->energy(x_next, state, cloth, contact));
  return out;
}

torch::Tensor total_energy(const TermList& terms, const torch::Tensor& x_next,
                           const FrameState& state, const ClothGeometry& cloth,
                           const BodyContact* contact) {
  torch::Tensor total = torch::zeros({}, x_next.options());
  for (const auto& t : terms) total = total + t->energy(x_next, state, cloth, contact);
  return total;
}

EnergyReport energy_report(const TermList& terms, const torch::Tensor& x_next,
                           const FrameState& state, const ClothGeometry& cloth,
                           const BodyContact* contact, const Material& material) {
  torch::NoGradGuard no_grad;
  FrameState evaluated = state;
  evaluated.material = material;
  EnergyReport report;
  for (auto& [name, e] : term_energies(terms, x_next.detach(), evaluated, cloth, contact)) {
    double v = e.item<double>();
    report.terms.emplace_back(name, v);
    report.total += v;
  }
  return report;
}

EnergyReport mean_report(const std::vector<EnergyReport>& reports) {
  if (reports.empty()) throw Error("energy report: no frames to average");
  EnergyReport mean = reports.front();
  for (size_t r = 1; r < reports.size(); ++r) {
    if (reports[r].terms.size() != mean.terms.size())
      throw Error("energy report: frames list different terms");
    for (size_t k = 0; k < mean.terms.size(); ++k) {
      if (reports[r].terms[k].first != mean.terms[k].first)
        throw Error("energy report: frames list different terms");
      mean.terms[k].second += reports[r].terms[k].second;
    }
    mean.total += reports[r].total;
    mean.residual_mm += reports[r].residual_mm;
  }
  double n = static_cast<double>(reports.size());
  for (auto& t : mean.terms) t.second /= n;
  mean.total /= n;
  mean.residual_mm /= n;
  return mean;
}

bool is_positive_term(const std::string& name) {
  return name == "stretch" || name == "bending" || name == "collision" || name == "repulsion";
}

double positive_energy(const EnergyReport& report) {
  double e = 0;
  for (const auto& [name, value] : report.terms)
    if (is_positive_term(name)) e += value;
  return e;
}

PositiveEnergyRange positive_energy_range(const std::vector<EnergyReport>& reports) {
  PositiveEnergyRange range;
  for (const auto& report : reports) {
    const double p = positive_energy(report);
    range.mean += p / reports.size();
    range.max = std::max(range.max, p);
  }
  return range;
}

std::vector<double> measured_residuals_mm(const std::vector<EnergyReport>& reports) {
  std::vector<double> measured;
  for (const auto& report : reports)
    if (std::isfinite(report.residual_mm)) measured.push_back(report.residual_mm);
  return measured;
}

double median_residual_mm(const std::vector<EnergyReport>& reports) { return median(measured_residuals_mm(reports)); }

MinimumSummary summarize_minimum(const std::vector<EnergyReport>& reports) {
  std::vector<double> distances, gaps;
  for (const auto& report : reports)
    if (std::isfinite(report.minimum_distance_mm)) {
      distances.push_back(report.minimum_distance_mm);
      gaps.push_back(report.minimum_gap_j);
    }
  MinimumSummary s;
  s.frames = int(distances.size());
  if (distances.empty()) return s;
  s.distance_median_mm = median(distances);
  s.distance_max_mm = *std::max_element(distances.begin(), distances.end());
  s.gap_median_j = median(gaps);
  return s;
}

}  // namespace pb4u

#include "pb4u/eval/frames_csv.h"

#include <cctype>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <limits>

#include "pb4u/physics/energy_report.h"
#include "pb4u/util/atomic_file.h"
#include "pb4u/util/error.h"

namespace pb4u {

void write_frames_csv(const std::string& path, const RolloutResult& r, const std::vector<ContactStepLog>* contact) {
  if (contact && contact->size() != r.reports.size())
    throw Error(path + ": " + std::to_string(contact->size()) + " contact logs for " +
                std::to_string(r.reports.size()) + " frames");
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  if (!parent.empty()) ensure_output_dir(parent.string());
  AtomicFile file(path);
  std::ostream& out = file.stream();
  out << std::setprecision(std::numeric_limits<double>::max_digits10);
  const bool body = !r.penetration.empty();
  bool sampled = false;  // frames solved on to their minimum (RolloutInput::minimum_every)
  for (const EnergyReport& e : r.reports) sampled = sampled || std::isfinite(e.minimum_distance_mm);
  out << "frame";
  if (!r.reports.empty())
    for (const auto& [name, value] : r.reports.front().terms) out << ',' << name;
  out << ",total,positive,residual_mm";
  if (sampled) out << ",distance_to_minimum_mm,energy_gap_j";
  if (body) out << ",penetrating_fraction,max_penetration_mm,edges_through_body,body_self_crossing_faces";
  if (contact) out << ",contact_excluded,caught_by_body,body_lag_mm";
  out << '\n';
  for (size_t f = 0; f < r.reports.size(); ++f) {
    const EnergyReport& e = r.reports[f];
    out << f + 1;
    for (const auto& [name, value] : e.terms) out << ',' << value;
    out << ',' << e.total << ',' << positive_energy(e) << ',' << e.residual_mm;
    if (sampled) out << ',' << e.minimum_distance_mm << ',' << e.minimum_gap_j;
    if (body) {
      const PenetrationFigures& p = r.penetration[f];
      out << ',' << p.penetrating_fraction << ',' << p.max_penetration_mm << ',' << p.edges_through << ','
          << p.body_self_crossing_faces;
    }
    if (contact) {
      const ContactStepLog& c = (*contact)[f];
      out << ',' << c.excluded << ',' << c.caught_by_body << ',' << 1e3 * c.body_lag;
    }
    out << '\n';
  }
  file.commit();
}

std::string file_name_from(const std::string& text) {
  std::string name;
  bool gap = false;
  for (char c : text) {
    const bool keep = std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-';
    if (!keep) {
      gap = true;
      continue;
    }
    if (gap && !name.empty()) name += '_';
    gap = false;
    name += c;
  }
  return name;
}

}  // namespace pb4u

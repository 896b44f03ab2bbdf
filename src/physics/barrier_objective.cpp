#include "pb4u/physics/barrier_objective.h"

namespace pb4u {

torch::Tensor PenaltyFallback::energy(const torch::Tensor& x) const {
  if (!active()) return torch::zeros({}, x.options());
  return collision_energy(x.index_select(0, rows), contact, term->eps(), term->weight());
}

torch::Tensor PenaltyFallback::stiffness(const torch::Tensor& x, const FrameState& state, const ClothGeometry& cloth,
                                         const BodyContact* full_contact) const {
  if (!active()) return {};
  const torch::Tensor all = term->contact_stiffness(x, state, cloth, full_contact);
  return torch::zeros({x.size(0)}, x.options()).index_copy(0, rows, all.index_select(0, rows));
}

PenaltyFallback penalty_fallback(const TermList& terms, const BodyContact* contact, const std::vector<char>& excluded) {
  PenaltyFallback f;
  for (const auto& term : terms)
    if (term->name() == "collision") f.term = dynamic_cast<const CollisionTerm*>(term.get());
  if (!f.term || !contact) return f;
  std::vector<int64_t> rows;
  for (size_t i = 0; i < excluded.size(); ++i)
    if (excluded[i]) rows.push_back(int64_t(i));
  if (rows.empty()) return f;
  f.rows = torch::tensor(rows, torch::kInt64).to(contact->point.device());
  f.contact.point = contact->point.index_select(0, f.rows);
  f.contact.normal = contact->normal.index_select(0, f.rows);
  return f;
}

}  // namespace pb4u

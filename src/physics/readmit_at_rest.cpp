// Cloth left out of barrier contact, readmitted where the solve stops (solver.readmit_at_rest).
#include "pb4u/physics/incremental_potential_solve.h"

#include <vector>

#include "pb4u/physics/barrier_potential.h"
#include "pb4u/physics/contact_candidates.h"
#include "pb4u/physics/intersection_free_start.h"
#include "pb4u/util/eigen_tensor.h"

namespace pb4u {
namespace reference_solve {

// Where the solve has stopped with cloth out of barrier contact, the penalty term has moved that
// cloth where it rests, and a push out of the whole cloth from there (as a start is:
// intersection_free_start) can free what the push of the released cloth alone, when the body
// got to its pose, could not: its neighbours move out with it. The push is kept only where it
// leaves every vertex in contact free; then the freed vertices rejoin contact, the ones still
// held stay with the penalty term where the push put them, and the solve goes on from there.
// False (the solve stops) when there is nothing to readmit, the push frees nothing or catches
// cloth that was in contact, or the step has made kReadmitsAtRest tries.
bool IncrementalPotentialSolve::readmit_at_rest() {
  if (!barrier || !config.readmit_at_rest || result.excluded == 0 || readmits_at_rest >= kReadmitsAtRest) return false;
  ++readmits_at_rest;
  const Eigen::MatrixXd out = pushed_out_of_body({});
  const std::vector<char> still =
      vertices_not_free_of(out, barrier->cloth_edges, body.V, body.F, barrier->settings.d_hat);
  int back = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const size_t k = size_t(i);
    if (still[k] && !excluded[k]) return false;  // it would catch cloth that was in contact
    if (excluded[k] && !still[k] && free_flags[k]) ++back;
  }
  if (back == 0) return false;
  for (Eigen::Index i = 0; i < n; ++i)
    if (excluded[size_t(i)] && !still[size_t(i)] && free_flags[size_t(i)]) rejoin_contact(size_t(i));
  result.readmitted_at_rest += back;
  q = free_coordinates(out, free, opts);
  if (strain) exclude_overstretched(out);  // edges the push stretched past the limit
  if (area) exclude_compressed(out);
  set_fallback();
  candidates = contact_candidates(out, {}, barrier->cloth_edges, body, {}, barrier->settings.d_hat);
  drop_pairs_of(excluded, barrier->cloth_edges, &candidates);
  history.clear();  // the objective changed
  E = evaluate(q, &g);
  return true;
}

}  // namespace reference_solve
}  // namespace pb4u

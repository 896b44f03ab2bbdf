// The solve's body and pins, kinematic under barrier contact: moved towards their pose at
// t + dt in CCD-certified moves that carry the cloth they touch, or placed there.
#include "pb4u/physics/incremental_potential_solve.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "pb4u/physics/barrier_potential.h"
#include "pb4u/physics/carried_by_body.h"
#include "pb4u/physics/contact_candidates.h"
#include "pb4u/physics/intersection_free_start.h"
#include "pb4u/util/eigen_tensor.h"

namespace pb4u {
namespace reference_solve {

// What is left of the pins' motion is pins_left(); the pins moved to `to` (k x 3).
void IncrementalPotentialSolve::move_pins(const Eigen::MatrixXd& to) {
  if (pin_rows.empty()) return;
  pin_now = to;
  x_base = x_base.index_copy(0, pin_index, matrix_to_tensor(pin_now, opts.dtype().toScalarType(), state.x.device()));
}

// The cloth pushed out of the body where it stands, as a start is (intersection_free_start):
// the rows `moved` selects (empty: every vertex); pins stay on their targets.
Eigen::MatrixXd IncrementalPotentialSolve::pushed_out_of_body(const std::vector<char>& moved) const {
  const Eigen::MatrixXd X = positions(q);
  Eigen::MatrixXd out = intersection_free_start(X, X, barrier->cloth_edges, body.V, body.F, barrier->settings.d_hat).x;
  for (Eigen::Index i = 0; i < n; ++i)
    if (!free_flags[size_t(i)] || (!moved.empty() && !moved[size_t(i)])) out.row(i) = X.row(i);
  return out;
}

// Where the body is still short of its pose after the moves it is allowed (cloth that left it
// no room and that no release freed) it is placed there; the cloth it now cuts or holds (pushed
// out of it first as a start is, with solver.push_out_caught) leaves barrier contact for the
// penalty term (SolverResult::excluded).
void IncrementalPotentialSolve::place_body(double left) {
  body.V = barrier->body_next;
  move_pins(pin_target);
  if (config.push_out_caught)  // the cloth the placed body now cuts or holds pushed out of it first
    q = free_coordinates(pushed_out_of_body({}), free, opts);
  const std::vector<char> held =
      vertices_not_free_of(positions(q), barrier->cloth_edges, body.V, body.F, barrier->settings.d_hat);
  for (size_t i = 0; i < held.size(); ++i)
    if (held[i] && !excluded[i]) {
      excluded[i] = 1;
      mark_caught(i);
      ++result.excluded;
      ++result.caught_by_body;
    }
  set_fallback();
  candidates = contact_candidates(positions(q), {}, barrier->cloth_edges, body, {}, barrier->settings.d_hat);
  drop_pairs_of(excluded, barrier->cloth_edges, &candidates);
  result.body_lag = left;
}

// Vertex i counted in SolverResult::caught_by_body (the caller counts it).
void IncrementalPotentialSolve::mark_caught(size_t i) {
  if (caught.empty()) caught.assign(size_t(n), 0);
  caught[i] = 1;
}

// Vertex i, left out of barrier contact, rejoins it (uncounted where it was counted).
void IncrementalPotentialSolve::rejoin_contact(size_t i) {
  excluded[i] = 0;
  --result.excluded;
  if (!released.empty()) released[i] = 0;
  if (!caught.empty() && caught[i]) {
    caught[i] = 0;
    --result.caught_by_body;
  }
}

// m: the longest move left to the body or a pin.
double IncrementalPotentialSolve::body_left() const {
  const double pins = pin_rows.empty() ? 0.0 : pins_left().rowwise().norm().maxCoeff();
  return std::max((barrier->body_next - body.V).rowwise().norm().maxCoeff(), pins);
}

// Once the body is at its pose, the cloth it passed over is pushed out of it as a start is;
// what that frees rejoins barrier contact (the rest stays with the penalty term).
void IncrementalPotentialSolve::readmit_released() {
  if (released.empty()) return;
  const Eigen::MatrixXd X = positions(q);
  Eigen::MatrixXd out = pushed_out_of_body(released);
  const std::vector<char> still = vertices_not_free_of(out, barrier->cloth_edges, body.V, body.F, barrier->settings.d_hat);
  int back = 0;
  for (Eigen::Index i = 0; i < n; ++i)
    if (released[size_t(i)] && !still[size_t(i)]) {
      rejoin_contact(size_t(i));
      ++back;
    } else if (released[size_t(i)]) {
      out.row(i) = X.row(i);
    }
  if (back == 0) return;
  q = free_coordinates(out, free, opts);
  set_fallback();
}

double body_move_cost(double size, bool cut) {
  if (!cut) return size / kMaxContactStep;
  return size > kMinBodyMove ? 0.0 : 1.0;
}

// The body's move of this iteration, the cloth it touches carried along and the pins by the
// same share of what is left of theirs, in CCD-certified parts (move_body_part; kShrinkBelow).
// False when nothing moved.
bool IncrementalPotentialSolve::move_body() {
  double left = body_left();
  if (left <= 0) return false;
  if (moves_allowed == 0)  // the step's first move: at least kMaxBodyMoves from here on
    moves_allowed = kMaxBodyMoves + (config.release_held_cloth ? std::ceil(left / kMaxContactStep) : 0.0);
  if (body_moves >= moves_allowed) {
    place_body(left);
    return true;
  }
  // One part, unless the iterations left need more of the motion in this one to bring the
  // body home (a refinement's few): then parts until that much is made.
  const double needed = left / double(std::max(1, config.max_iterations - result.iterations));
  double done = 0;
  bool moved = false;
  for (int part = 0; part < kMoveParts && left > 0; ++part) {
    if (part > 0 && body_moves >= moves_allowed) {  // each part is a move
      place_body(left);
      return true;
    }
    const double size = std::min(move_size, left);
    const double t = move_body_part(size, left, &moved);
    const bool cut = t < kShrinkBelow;
    body_moves += body_move_cost(size, cut);
    move_size = cut ? std::max(kMinBodyMove, move_size * std::max(0.1, t)) : std::min(kMaxContactStep, 2 * move_size);
    if (!(t > 0) && move_size <= kMinBodyMove) break;
    done += t * size;
    left = body_left();
    if (done >= needed) break;
  }
  return moved;
}

// One part of a body move: `size` m of the `left` still to go, cut to what CCD certifies.
// Returns the share of the part taken; *moved is set when the body, a pin or the cloth's
// contact changed.
double IncrementalPotentialSolve::move_body_part(double size, double left, bool* moved) {
  const double share = left > size ? size / left : 1.0;
  const Eigen::MatrixXd DB = share * (barrier->body_next - body.V);
  const Eigen::MatrixXd X = positions(q);
  Eigen::MatrixXd D = carried_by_body(X, barrier->cloth_edges, body, DB, excluded, barrier->settings.d_hat / 2,
                                      config.body_carry == "ride");
  for (Eigen::Index i = 0; i < n; ++i)
    if (!free_flags[size_t(i)]) D.row(i).setZero();
  const Eigen::MatrixXd DP = share * pins_left();
  for (size_t j = 0; j < pin_rows.size(); ++j) D.row(pin_rows[j]) = DP.row(Eigen::Index(j));
  candidates = contact_candidates(X, D, barrier->cloth_edges, body, DB, barrier->settings.d_hat);
  drop_pairs_of(excluded, barrier->cloth_edges, &candidates);
  double t = max_safe_step(X, D, barrier->cloth_edges, body, DB, candidates);
  // Cloth that holds the move back would stall the body for the rest of the step, and the
  // body would then be placed at its pose onto everything in its way. With
  // solver.release_held_cloth the vertices of the pairs that allow less than kHeldBelow of
  // the move leave barrier contact (caught by the body, for the penalty term), and the move
  // is certified again without them.
  bool released_now = false;
  for (int round = 0; config.release_held_cloth && round < kReleaseRounds && t < kHeldBelow; ++round) {
    const std::vector<char> holding =
        vertices_holding_step(X, D, barrier->cloth_edges, body, DB, candidates, kHeldBelow);
    int newly = 0;
    for (Eigen::Index i = 0; i < n; ++i)
      if (holding[size_t(i)] && !excluded[size_t(i)]) {  // a pin too: it stays on its path, out of contact
        if (released.empty()) released.assign(size_t(n), 0);
        excluded[size_t(i)] = released[size_t(i)] = 1;
        mark_caught(size_t(i));
        ++newly;
      }
    if (newly == 0) break;
    result.excluded += newly;
    result.caught_by_body += newly;
    result.released += newly;
    released_now = true;
    drop_pairs_of(excluded, barrier->cloth_edges, &candidates);
    t = max_safe_step(X, D, barrier->cloth_edges, body, DB, candidates);
  }
  if (released_now) {
    set_fallback();  // the objective changed: the caller evaluates it again
    *moved = true;
  }
  if (!(t > 0)) return 0;
  // A full step lands exactly on the pose and the pins' targets (no rounding left over).
  const bool home = t >= 1 && share >= 1;
  body.V = home ? barrier->body_next : Eigen::MatrixXd(body.V + t * DB);
  move_pins(home ? pin_target : Eigen::MatrixXd(pin_now + t * DP));
  q = q + t * free_coordinates(D, free, opts);
  if (home) readmit_released();
  *moved = true;
  return std::min(t, 1.0);
}

}  // namespace reference_solve
}  // namespace pb4u

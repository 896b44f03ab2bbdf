#include "pb4u/physics/reference_solver.h"

#include <algorithm>
#include <string>
#include <vector>

#include "pb4u/body/outer_faces.h"
#include "pb4u/mesh/edges.h"
#include "pb4u/physics/body_offset.h"
#include "pb4u/physics/incremental_potential_solve.h"
#include "pb4u/util/eigen_tensor.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace {

// solver.penalty_faces = outer: the rows of the body's faces no other part of it covers at
// t + dt; empty where none is covered.
std::vector<int64_t> uncovered_face_rows(const FrameState& state) {
  const std::vector<char> covered =
      covered_faces(tensor_to_matrix(state.body.next_vertices), index_tensor_to_matrix(state.body.faces));
  std::vector<int64_t> rows;
  if (std::find(covered.begin(), covered.end(), char(1)) == covered.end()) return rows;
  for (size_t f = 0; f < covered.size(); ++f)
    if (!covered[f]) rows.push_back(int64_t(f));
  return rows;
}

}  // namespace

SolverResult solve_reference_step(const FrameState& state, const ClothGeometry& cloth,
                                  const TermList& terms, const BodyContact* contact,
                                  const ReferenceSolverConfig& config, const BarrierStepInput* barrier,
                                  const torch::Tensor* x_start) {
  const std::optional<BodyContact> outer = barrier ? barrier->solved_contact(state, contact) : std::nullopt;
  return reference_solve::IncrementalPotentialSolve(state, cloth, terms, outer ? &*outer : contact, config, barrier,
                                                    x_start)
      .run();
}

std::optional<BodyContact> BarrierStepInput::solved_contact(const FrameState& state, const BodyContact* contact) const {
  if (outer_faces.empty() || !contact) return std::nullopt;
  return contact_on_faces(*contact, state.x, state.body, outer_faces);  // the step's degenerate area
}

bool BarrierStepInput::drops(const PhysicsTerm& term) const { return !keeps_penalty && term.name() == "collision"; }

std::optional<BarrierStepInput> barrier_step_input(const FrameState& state, const ClothGeometry& cloth,
                                                   const ReferenceSolverConfig& config) {
  if (config.contact != "barrier" || !state.effects.collision || !state.body.defined()) return std::nullopt;
  BarrierStepInput input;
  input.body_t = tensor_to_matrix(state.body.vertices);
  input.body_next = tensor_to_matrix(state.body.next_vertices);
  input.body_faces = index_tensor_to_matrix(state.body.faces);
  if (config.barrier_offset > 0) {  // the body moved out along its normals where it has room
    input.body_t = offset_where_room(input.body_t, input.body_faces, config.barrier_offset);
    input.body_next = offset_where_room(input.body_next, input.body_faces, config.barrier_offset);
  }
  input.cloth_edges = unique_edges(index_tensor_to_matrix(cloth.faces));
  input.settings.d_hat = config.barrier_distance;
  input.settings.stiffness = config.barrier_stiffness;
  input.keeps_penalty = config.barrier_keeps_penalty;
  using GivenStart = BarrierStepInput::GivenStart;
  input.given_start = config.given_start == "at_step"            ? GivenStart::at_step
                      : config.given_start == "swept"            ? GivenStart::swept
                      : config.given_start == "fewer_left_out"   ? GivenStart::fewer_left_out
                      : config.given_start == "swept_if_left_out" ? GivenStart::swept_if_left_out
                                                                 : GivenStart::at_step;
  // fewer_left_out_to_tolerance is at_step here: a refinement (refined_step) gives its solve to
  // the tolerance fewer_left_out itself.
  if (config.penalty_faces == "outer") input.outer_faces = uncovered_face_rows(state);
  if (config.barrier_stiffness_max > 0 && config.barrier_stiffness_max < config.barrier_stiffness)
    throw Error("reference solver: solver.barrier_stiffness_max (" + std::to_string(config.barrier_stiffness_max) +
                ") is below solver.barrier_stiffness (" + std::to_string(config.barrier_stiffness) + ")");
  return input;
}

SolverResult solve_reference_frame(const FrameState& state, const ClothGeometry& cloth,
                                   const TermList& terms, const PhysicsConfig& config) {
  std::optional<BodyContact> contact = body_contact_for(state, config);
  const std::optional<BarrierStepInput> barrier = barrier_step_input(state, cloth, config.solver);
  return solve_reference_step(state, cloth, terms, contact ? &*contact : nullptr, config.solver,
                              barrier ? &*barrier : nullptr);
}

}  // namespace pb4u

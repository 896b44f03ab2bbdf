#pragma once
// The reference solver's solve of one frame (physics/reference_solver.h: solve_reference_step
// builds one and runs it). Its parts: the start, the objective and the step
// (incremental_potential_solve.cpp), and the kinematic body and pins
// (kinematic_body_moves.cpp). Callers outside src/physics/ use reference_solver.h.
#include <torch/torch.h>

#include <Eigen/Core>

#include <chrono>
#include <deque>
#include <functional>
#include <limits>
#include <memory>
#include <vector>

#include "pb4u/physics/area_barrier.h"
#include "pb4u/physics/barrier_objective.h"
#include "pb4u/physics/contact_candidates.h"
#include "pb4u/physics/coordinate_hessian.h"
#include "pb4u/physics/elastic_solve.h"
#include "pb4u/physics/reference_solver.h"
#include "pb4u/physics/strain_barrier.h"

namespace pb4u {
namespace reference_solve {

// m: the longest move of a vertex (cloth or body) in one line search of the intersection-free solve.
constexpr double kMaxContactStep = 5e-2;
// CCD-certified body moves per step (with solver.release_held_cloth: beyond the ones its motion
// needs at kMaxContactStep each; a limb swinging 70 cm in a frame needs 14); a move cut and
// tried again smaller is not counted (kShrinkBelow), one taken whole counts its share of
// kMaxContactStep, so a body that keeps moving in small moves is not placed for their number;
// a body not at its pose after them is placed there.
constexpr int kMaxBodyMoves = 24;
// A body move that some cloth allows less than this fraction of is held back by it (pinched
// between two body parts, or an edge dragged against a body edge it cannot pass); rounds of
// leaving that cloth out of barrier contact before the move is taken as it is.
constexpr double kHeldBelow = 0.1;
constexpr int kReleaseRounds = 4;
// A body move cut by CCD below kShrinkBelow of itself is followed by one of what CCD allowed
// (at least a tenth of it, and no less than kMinBodyMove), one taken whole by one twice as long
// (up to kMaxContactStep), from iteration to iteration; a move at kMinBodyMove that is cut counts
// a whole move towards kMaxBodyMoves. The carry (carried_by_body.h) is exact to first order in the
// move: a 5 cm move of a limb that turns under a 13 cm cloth edge ends its pairs nearer than
// the carry kept them, and CCD then cut every move that followed to a sliver (the hard cases'
// jump at speed 2 from the settled start: its first frame's body stalled 246 mm short of its
// pose, 61 vertices caught); in moves of a centimetre, the cloth relaxing between them, those
// pairs stay apart. Where few iterations are left (a refinement's 10) an iteration's move is
// made of up to kMoveParts such parts, each counted as a move, until it has made what the body
// needs a move to get home.
constexpr double kShrinkBelow = 0.5;
constexpr double kMinBodyMove = 1e-3;
constexpr int kMoveParts = 8;
// Tries a step makes at readmitting the cloth left out of contact where its solve stops
// (solver.readmit_at_rest).
constexpr int kReadmitsAtRest = 2;
// What a body move of `size` m counts towards kMaxBodyMoves: taken whole, its share of
// kMaxContactStep (a body that keeps moving in small moves is not placed for their number);
// cut (below kShrinkBelow), nothing while it can be tried again smaller, a whole move at
// kMinBodyMove.
double body_move_cost(double size, bool cut);
// Rounds of Provot's pass and the push out of the body that make a start both intersection-free
// and within the strain limit (solver.strain_limit).
constexpr int kStartRounds = 10;

// The rows `free` of an n x 3 matrix, flat (3 x free rows): the solver's coordinates.
torch::Tensor free_coordinates(const Eigen::MatrixXd& rows, const torch::Tensor& free, const torch::TensorOptions& opts);

struct Pair {
  torch::Tensor s, y;
  double rho;
};

// r (3k, xyz per vertex) -> H0^-1 r.
using InverseHessian = std::function<torch::Tensor(const torch::Tensor&, const std::deque<Pair>&)>;

// L-BFGS two-loop recursion: approximately H^-1 g, starting from H0^-1.
torch::Tensor lbfgs_direction(const torch::Tensor& g, const std::deque<Pair>& history, const InverseHessian& initial);

// One frame's solve: argmin over the free cloth coordinates of the incremental potential (the
// physics terms, with barrier contact the barriers of solver.contact / strain_limit /
// area_barrier_gap), by L-BFGS or projected Newton. With barrier contact the body and the pins
// are kinematic: each iteration first moves them on towards their pose at t + dt as far as CCD
// certifies (move_body), then takes one step of the cloth where they stand.
// The members are the solve's state; the constructor sets up the start, run() iterates.
class IncrementalPotentialSolve {
 public:
  IncrementalPotentialSolve(const FrameState& state, const ClothGeometry& cloth, const TermList& terms,
                            const BodyContact* contact, const ReferenceSolverConfig& config,
                            const BarrierStepInput* barrier, const torch::Tensor* x_start);
  SolverResult run();

 private:
  // --- the start ---
  void place_ballistic_start(const torch::Tensor* x_start);
  void shorten_start_edges();
  void make_barrier_start(const torch::Tensor* x_start);
  void make_inverse_hessian();
  void pick_start();
  // --- edges and faces left out of their barriers ---
  void exclude_overstretched(const Eigen::MatrixXd& X);
  void exclude_compressed(const Eigen::MatrixXd& X);
  void readmit_relaxed_edges_and_faces();
  void set_fallback();
  // --- the objective ---
  Eigen::MatrixXd positions(const torch::Tensor& q) const;
  double evaluate(const torch::Tensor& q, torch::Tensor* grad);
  torch::Tensor contact_diagonal(const torch::Tensor& q, CoordinateHessian* blocks);
  void factorize();
  // --- the body and the pins, kinematic ---
  Eigen::MatrixXd pins_left() const { return pin_target - pin_now; }
  void move_pins(const Eigen::MatrixXd& to);
  Eigen::MatrixXd pushed_out_of_body(const std::vector<char>& moved) const;
  void place_body(double left);
  double body_left() const;
  void mark_caught(size_t i);
  void rejoin_contact(size_t i);
  void readmit_released();
  bool readmit_at_rest();
  bool move_body();
  double move_body_part(double size, double left, bool* moved);
  // --- one iteration's step ---
  double feasible_step(const torch::Tensor& d, const char** blocked_by);
  bool line_search(const torch::Tensor& d, double slope, double t, torch::Tensor* q_new, torch::Tensor* g_new,
                   double* E_new);
  void accept(const torch::Tensor& q_new, const torch::Tensor& g_new, double E_new);
  // -vv: one line per iteration (its direction, what of it was taken and why, the decrease).
  void trace_iteration(const torch::Tensor& d, const torch::Tensor& q_new, double t_feasible, double E_new,
                       double slope) const;
  void adapt_barrier_stiffness();
  SolverResult finish();
  bool small_decrease(double slope) const {
    return config.decrease_tolerance > 0 && -0.5 * slope < config.decrease_tolerance;
  }

  const FrameState& state;
  const ClothGeometry& cloth;
  const TermList& terms;
  const BodyContact* contact;
  const ReferenceSolverConfig& config;
  const BarrierStepInput* barrier;
  const torch::TensorOptions opts;
  const int64_t n;
  const std::chrono::steady_clock::time_point start_time = std::chrono::steady_clock::now();

  SolverResult result;
  torch::Tensor x_base;  // (n, 3): the start, and where the held rows stay
  // The solver's own start, kept beside a given step: without barrier contact both are feasible,
  // and the solve starts from whichever is lower in its objective (SolverResult::own_start).
  torch::Tensor x_own;
  // The cloth where it stands at t, pins at their targets: without barrier contact, a third start
  // where the ballistic prediction is higher (SolverResult::standing_start).
  torch::Tensor x_standing;
  // The ballistic prediction beside a given step, with barrier contact and
  // solver.own_start_where_left_out: the start where the given step's start leaves vertices out.
  torch::Tensor x_ballistic;
  torch::Tensor pinned;  // (n,) bool
  torch::Tensor free;    // the free rows; q holds their coordinates
  int64_t nf = 0;
  std::vector<char> pinned_flags;  // per vertex: the start's Provot passes hold them, the barrier moves them
  std::vector<char> free_flags;
  std::vector<int> row;  // vertex -> its free row, -1 when held

  // Strain barrier (solver.strain_limit).
  bool strain = false;
  Eigen::MatrixXi strain_edges;
  Eigen::VectorXd rest_length;
  std::vector<char> strain_excluded;
  StrainBarrierSettings strain_settings;
  // Area barrier (solver.area_barrier_gap).
  bool area = false;
  AreaBarrierSettings area_settings;
  Eigen::MatrixXi area_faces;
  Eigen::VectorXd rest_area;
  std::vector<char> area_excluded;
  // Barrier contact: the body where it stands, the pairs within reach, the cloth left out.
  ContactSurface body;
  ContactCandidates candidates;
  BarrierSettings settings;
  double closest = std::numeric_limits<double>::infinity();  // m: nearest pair at the last evaluation
  double accepted_closest = std::numeric_limits<double>::infinity();
  std::vector<char> excluded;
  PenaltyFallback fallback;
  // Pins are kinematic under barrier contact, as the body is. pin_now / pin_target: the pinned
  // rows, k x 3.
  std::vector<int64_t> pin_rows;
  Eigen::MatrixXd pin_now, pin_target;
  torch::Tensor pin_index;
  const Eigen::MatrixXd* body_start = nullptr;  // the body where the solve starts
  double body_moves = 0, moves_allowed = 0;  // counted as body_move_cost() says; 0 allowed: not yet moved
  double move_size = kMaxContactStep;  // m: the next part of a body move (kShrinkBelow)
  std::vector<char> released;  // per cloth vertex: left out of contact so that the body could move on
  std::vector<char> caught;    // per cloth vertex: counted in SolverResult::caught_by_body
  int readmits_at_rest = 0;    // readmit_at_rest() tries this step (kReadmitsAtRest at most)

  // The step.
  InverseHessian initial;
  std::shared_ptr<ElasticSolve> elastic;
  bool newton = false;
  bool factorized = false;
  bool had_blocks = false;  // the last factorisation held barrier blocks
  torch::Tensor q, g;
  double E = 0;
  std::deque<Pair> history;
  double step_norm = 0;
  double last_slope = 0;  // g.d of the last direction
  const char* stopped_by = nullptr;  // why the loop ended (the debug log says)
  const char* step_bound = "nothing";  // what cut the last direction short (feasible_step; the trace says)
};

}  // namespace reference_solve
}  // namespace pb4u

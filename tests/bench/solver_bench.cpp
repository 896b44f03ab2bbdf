// Reference solver (SPEC 8): time per frame and energy reached vs the L-BFGS iteration budget,
// at three garment resolutions. The scene: a square cloth falling onto a sphere (gravity,
// collision, friction). Each resolution is warmed up for a few fully solved frames, then the
// same next frame is solved with every budget; timings are medians of repeated solves.
// Usage: solver_bench [warm-up frames = 6] [repeats = 5] [threads = 0 (all)] [history = config]
//                     [largest grid = 40] [initial Hessian = elastic | inertia]
//                     [step = quasi_newton | newton] [contact = penalty | barrier]
#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "../physics/physics_test_util.h"
#include "pb4u/physics/reference_solver.h"
#include "pb4u/util/runtime.h"
#include "test_util.h"

using namespace pb4u;

int main(int argc, char** argv) {
  ensure_fast_runtime(argc, argv);
  const int warmup = argc > 1 ? std::atoi(argv[1]) : 6;
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 5;
  const int threads = configure_threads(argc > 3 ? std::atoi(argv[3]) : 0);
  const int history = argc > 4 ? std::atoi(argv[4]) : ReferenceSolverConfig{}.history;
  const int largest = argc > 5 ? std::atoi(argv[5]) : 40;
  const std::string initial = argc > 6 ? argv[6] : ReferenceSolverConfig{}.initial_hessian;
  const std::string step = argc > 7 ? argv[7] : ReferenceSolverConfig{}.step;
  const std::string contact = argc > 8 ? argv[8] : ReferenceSolverConfig{}.contact;
  std::vector<int> resolutions;
  for (int n : {10, 20, 40})
    if (n <= largest) resolutions.push_back(n);
  const std::vector<int> budgets = {5, 10, 20, 50, 100, 200, 400};
  const double radius = 0.25;

  const int subdivisions = 4;
  std::printf("solver_bench: cloth 0.6 m square dropped on a sphere (r = %.2f m, %d faces), "
              "float64, %d threads, L-BFGS history %d, initial Hessian %s, step %s, contact %s\n", radius,
              20 << (2 * subdivisions), threads, history, initial.c_str(), step.c_str(), contact.c_str());
  std::printf("| grid | vertices | triangles | budget | iterations | evaluations | ms/frame (median) | energy (J) | "
              "energy - best (J) | max grad (N) | step (m) | converged |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (int n : resolutions) {
    TriMesh g;
    FrameState state = test::cloth_above_sphere(n, 0.6, radius, 0.01, subdivisions, &g);
    ClothGeometry cloth = make_cloth_geometry(g);
    PhysicsConfig config;
    config.solver.history = history;
    config.solver.initial_hessian = initial;
    config.solver.step = step;
    config.solver.contact = contact;
    TermList terms = build_terms(state.effects, config);
    config.solver.max_iterations = budgets.back();
    for (int f = 0; f < warmup; ++f) {
      SolverResult r = solve_reference_frame(state, cloth, terms, config);
      state.x_prev = state.x;
      state.x = r.x_next;
    }

    struct Row { int budget, iterations, evaluations; double ms, energy, grad, scaled; bool converged; };
    std::vector<Row> rows;
    for (int budget : budgets) {
      config.solver.max_iterations = budget;
      std::vector<double> ms;
      SolverResult r;
      for (int k = 0; k < repeats; ++k) {
        auto t0 = std::chrono::steady_clock::now();
        r = solve_reference_frame(state, cloth, terms, config);  // contact query included
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      }
      std::sort(ms.begin(), ms.end());
      rows.push_back({budget, r.iterations, r.evaluations, ms[ms.size() / 2], r.energy, r.gradient_norm, r.step_norm, r.converged});
    }
    double best = rows.front().energy;
    for (const Row& r : rows) best = std::min(best, r.energy);
    for (const Row& r : rows)
      std::printf("| %d | %lld | %lld | %d | %d | %d | %.1f | %.9f | %.3e | %.2e | %.2e | %s |\n", n,
                  static_cast<long long>(cloth.num_vertices), static_cast<long long>(g.F.rows()),
                  r.budget, r.iterations, r.evaluations, r.ms, r.energy, r.energy - best, r.grad, r.scaled,
                  r.converged ? "yes" : "no");
    std::fflush(stdout);
  }
  return 0;
}

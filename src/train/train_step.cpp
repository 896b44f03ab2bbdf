// The training step (Trainer::train_step): each of the step's samples continues a replay chain
// or starts a fresh LBS-initialised trajectory, rolls the model out and accumulates its
// gradients; the ranks sum gradients, losses and normaliser statistics in one buffer; Adam
// steps unless anything was non-finite.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <torch/cuda.h>

#include "pb4u/data/lbs_frame.h"
#include "pb4u/graph/build_graph.h"
#include "pb4u/graph/online_normalizer.h"
#include "pb4u/mesh/geometry.h"
#include "pb4u/model/euler_step.h"
#include "pb4u/model/propagation_control.h"
#include "pb4u/physics/body_queries.h"
#include "pb4u/physics/energy_report.h"
#include "pb4u/physics/physics_term.h"
#include "pb4u/physics/step_constraints.h"
#include "pb4u/rollout/refined_step.h"
#include "pb4u/scene/pins.h"
#include "pb4u/train/trainer.h"
#include "pb4u/util/eigen_tensor.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace {

// The state as the solver takes it: float64 (positions) on the CPU.
FrameState on_cpu_float64(const FrameState& state) {
  FrameState s = state;
  for (torch::Tensor* t : {&s.x, &s.x_prev, &s.pin_targets, &s.body.vertices, &s.body.next_vertices})
    if (t->defined()) *t = t->to(torch::kCPU, torch::kFloat64);
  for (torch::Tensor* t : {&s.pinned, &s.body.faces})
    if (t->defined()) *t = t->to(torch::kCPU);
  return s;
}

// Global sample g of step `step`: its own RNG, independent of the rank that draws it.
std::mt19937_64 sample_rng(int seed, int64_t step, int64_t g) {
  std::seed_seq seq{static_cast<uint32_t>(seed), static_cast<uint32_t>(step),
                    static_cast<uint32_t>(step >> 32), static_cast<uint32_t>(g)};
  return std::mt19937_64(seq);
}

std::vector<OnlineNormalizerImpl*> normalisers(torch::nn::Module& model) {
  std::vector<OnlineNormalizerImpl*> out;
  for (const auto& m : model.modules())
    if (auto* n = dynamic_cast<OnlineNormalizerImpl*>(m.get())) out.push_back(n);
  return out;
}

bool normalisers_warming_up(torch::nn::Module& model) {
  for (auto* n : normalisers(model))
    if (!n->frozen()) return true;
  return false;
}

// Every normaliser's (accumulations, count, sum, sum_squares), flat float64 on the CPU.
torch::Tensor normaliser_statistics(torch::nn::Module& model) {
  std::vector<torch::Tensor> parts;
  for (auto* n : normalisers(model))
    for (const auto& t : {n->accumulations, n->count, n->sum, n->sum_squares})
      parts.push_back(t.detach().to(torch::kCPU, torch::kFloat64).reshape({-1}));
  return torch::cat(parts);
}

void set_normaliser_statistics(torch::nn::Module& model, const torch::Tensor& flat) {
  torch::NoGradGuard no_grad;
  int64_t offset = 0;
  for (auto* n : normalisers(model))
    for (auto* t : {&n->accumulations, &n->count, &n->sum, &n->sum_squares}) {
      torch::Tensor part = flat.narrow(0, offset, t->numel()).view(t->sizes());
      if (t->scalar_type() == torch::kInt64) part = part.round();
      t->copy_(part.to(t->options()));
      offset += t->numel();
    }
}

}  // namespace

Trajectory Trainer::fresh_trajectory(std::mt19937_64& rng, int rollout) {
  // Garment, motion of its body, start frame, material, effects (and pins).
  Trajectory tr;
  tr.garment = std::uniform_int_distribution<int>(0, int(data_.garments.size()) - 1)(rng);
  const int bi = data_.garment_body[tr.garment];
  std::vector<int> motions;
  for (int m = 0; m < int(data_.motions.size()); ++m)
    if (data_.motion_body[m] == bi) motions.push_back(m);
  if (motions.empty()) throw Error(config_.data.dataset + ": no training motion for body " + data_.bodies[bi].name);
  tr.motion = motions[std::uniform_int_distribution<size_t>(0, motions.size() - 1)(rng)];
  const Motion& motion = data_.motions[tr.motion];
  const int r = std::min(rollout, std::max(1, motion.num_frames() - 2));
  tr.frame = std::uniform_int_distribution<int>(1, std::max(1, motion.num_frames() - 1 - r))(rng);
  tr.material = sample_material(config_.materials, Material{}, rng);
  tr.effects = sample_effects(config_.effects, rng);
  // One factor draws nothing, so runs without scales keep their samples.
  const auto& scales = config_.data.scales;
  if (scales.size() > 1) tr.scale = std::uniform_int_distribution<int>(0, int(scales.size()) - 1)(rng);
  const double c = scales[tr.scale];

  const Garment& garment = data_.garments[tr.garment];
  LbsFrame frame = lbs_frame(data_.bodies[bi], garment, motion, tr.frame, config_.data.push_out_gap);
  tr.x = matrix_to_tensor(frame.garment * c, torch::kFloat32, device_);
  tr.x_prev = matrix_to_tensor(frame.garment_prev * c, torch::kFloat32, device_);
  const bool waistband = tr.effects.needs_body() && config_.waistband.holds(garment.name);
  if (waistband) tr.effects.pins = true;
  if (tr.effects.pins) {
    tr.pinned = torch::zeros({tr.x.size(0)}, torch::TensorOptions().dtype(torch::kBool));
    for (int i : waistband ? top_band_vertices(garment.mesh.V, config_.waistband.band)
                           : sample_pinned_vertices(garment.mesh.V, rng))
      tr.pinned[i] = true;
    tr.pinned = tr.pinned.to(device_);
    tr.pin_anchor = tr.x.clone();
  }
  return tr;
}

Trainer::SampleResult Trainer::train_sample(std::mt19937_64& rng, int slot, int rollout, double collision_weight) {
  SampleResult result;
  // Continue one of this slot's replay chains, or start fresh (and put it in that chain).
  const ReplayConfig& replay = config_.replay;
  int chain = -1;
  Trajectory tr;
  if (replay.chains > 0) {
    if (chains_.size() <= size_t(slot)) chains_.resize(slot + 1);
    chains_[slot].resize(replay.chains);
    chain = std::uniform_int_distribution<int>(0, replay.chains - 1)(rng);
    const bool fresh = std::uniform_real_distribution<double>(0, 1)(rng) < replay.p_fresh;
    if (!fresh && chains_[slot][chain].active()) tr = chains_[slot][chain];
  }
  if (!tr.active()) tr = fresh_trajectory(rng, rollout);
  lap("sample: LBS start");
  const double c = config_.data.scales[tr.scale];
  result.K = sample_propagation_steps(config_.model, rng, 1.0 / c);
  result.age = tr.age;

  const int gi = tr.garment;
  const Body& body = data_.bodies[data_.garment_body[gi]];
  const Garment& garment = data_.garments[gi];
  const Motion& motion = data_.motions[tr.motion];
  const int r = std::max(1, std::min(rollout, motion.num_frames() - 1 - tr.frame));
  result.rollout = r;

  FrameState state;
  state.x = tr.x;
  state.x_prev = tr.x_prev;
  state.effects = tr.effects;
  state.material = tr.material;
  state.pinned = tr.pinned;
  const torch::Tensor body_faces = index_matrix_to_tensor(body.mesh.F, device_);
  // Poses stay at the motion's size (lbs_garment needs them so); the state gets them times c.
  auto pose = [&](int k) { return pose_body(body, motion.frames[std::clamp(k, 0, motion.num_frames() - 1)]); };
  Eigen::MatrixXd body_now = pose(tr.frame), body_next = pose(tr.frame + 1);
  lap("body poses, pins");

  TermList terms =
      build_terms(tr.effects, config_.physics, collision_weight, repulsion_weight(config_.physics.repulsion, step_));
  torch::Tensor loss_sum = torch::zeros({}, torch::TensorOptions().device(device_));
  std::vector<double> term_sums(terms.size(), 0.0);
  double last_positive = 0;  // of the last step: does the chain stay plausible?
  for (int i = 0; i < r; ++i) {
    if (tr.effects.needs_body()) {
      state.body.vertices = matrix_to_tensor(body_now * c, torch::kFloat32, device_);
      state.body.next_vertices = matrix_to_tensor(body_next * c, torch::kFloat32, device_);
      state.body.faces = body_faces;
    } else {
      state.body = BodyFrame{};
    }
    if (tr.effects.pins) {
      // With a body the pins ride on the skinned garment; without one they stay put.
      state.pin_targets = tr.effects.needs_body()
                              ? matrix_to_tensor(lbs_garment(body, garment, motion, tr.frame + i + 1, body_next,
                                                             config_.data.push_out_gap) * c,
                                                 torch::kFloat32, device_)
                              : tr.pin_anchor;
    }
    lap("body poses, pins");
    const int vi = variant(gi, tr.scale);
    GraphBatch graph = build_graph(state, topology_[vi], config_.model.graph_options());
    lap("graph build");
    StageTimes forward_times;
    torch::Tensor accel = model_->forward(graph, result.K, profile_ ? &forward_times : nullptr);
    torch::Tensor x_next = euler_step(state, accel);
    if (profile_) {
      lap("forward: decode, Euler");  // the whole forward, then its stages moved out of it
      for (const auto& [stage, ms] : {std::pair<const char*, double>{"forward: encode", forward_times.encode},
                                      {"forward: propagation + update", forward_times.propagate},
                                      {"forward: blocks", forward_times.blocks}}) {
        profile_->add(stage, ms);
        profile_->add("forward: decode, Euler", -ms);
      }
    }
    std::optional<BodyContact> contact = body_contact_for(state, config_.physics);
    lap("contact query");
    torch::Tensor step_loss = torch::zeros({}, x_next.options());
    last_positive = 0;
    for (size_t k = 0; k < terms.size(); ++k) {
      const torch::Tensor e = terms[k]->energy(x_next, state, cloth_[vi], contact ? &*contact : nullptr);
      step_loss = step_loss + e;
      const double v = e.item<double>();
      term_sums[k] += v;
      if (is_positive_term(terms[k]->name())) last_positive += v;
      if (profile_) lap(("term: " + terms[k]->name()).c_str());
    }
    loss_sum = loss_sum + step_loss.detach();
    step_loss.backward();  // gradients accumulate; the next step starts from a detached state
    lap("backward");
    torch::Tensor x_carried = x_next.detach();
    if (replay.constrains()) {
      x_carried = constrain_step(x_carried, state, contact ? &*contact : nullptr, topology_[vi],
                                 replay.strain_limit, replay.contact_projection);
      lap("replay: constrain the state carried on");
    }
    if (replay.refine_iterations > 0) {
      const FrameState s = on_cpu_float64(state);
      ReferenceSolverConfig solver = config_.physics.solver;
      solver.contact = replay.refine_contact;
      const std::optional<BodyContact> c64 = body_contact_for(s, config_.physics);
      RefineConfig refine;
      refine.iterations = replay.refine_iterations;
      refine.step = solver.step;  // the solver's own step (auto: L-BFGS with penalty contact), as in docs/training.md
      const torch::Tensor refined = refine_step(x_carried, s, refine_cloth_[size_t(vi)], build_terms(s.effects, config_.physics),
                                                c64 ? &*c64 : nullptr, solver, refine);
      x_carried = refined.to(x_carried.device(), x_carried.scalar_type());
      lap("replay: refine the state carried on");
    }
    state.x_prev = state.x;
    state.x = x_carried;
    if (i + 1 < r) {
      body_now = body_next;
      body_next = pose(tr.frame + i + 2);
    }
  }
  result.loss = loss_sum.item<double>() / r;
  for (size_t k = 0; k < terms.size(); ++k) result.terms.emplace_back(terms[k]->name(), term_sums[k] / r);
  if (chain >= 0) {
    tr.x = state.x;
    tr.x_prev = state.x_prev;
    tr.frame += r;
    tr.age += r;
    const bool room = tr.frame + 1 < motion.num_frames() - 1;
    const bool plausible = std::isfinite(last_positive) && last_positive < replay.restart_energy &&
                           std::isfinite(result.loss);
    chains_[slot][chain] = room && plausible ? tr : Trajectory{};
  }
  lap("body poses, pins");
  return result;
}

void Trainer::lap(const char* stage) {
  if (!profile_) return;
  if (device_.is_cuda()) torch::cuda::synchronize();
  profile_->lap(stage);
}

StepResult Trainer::train_step() {
  auto t0 = std::chrono::steady_clock::now();
  if (profile_) profile_->begin_step();
  model_->train();
  StepResult result;
  result.step = step_ + 1;
  const int rollout = rollout_length(config_.curriculum, step_);
  result.lr = learning_rate(config_.optim, step_, config_.run.steps);
  result.collision_weight = collision_weight(config_.physics.collision, step_);
  for (auto& group : optimizer_->param_groups())
    static_cast<torch::optim::AdamOptions&>(group.options()).lr(result.lr);

  const int batch = config_.run.batch;
  const int rank = group_ ? group_->rank() : 0;
  auto params = model_->parameters();
  int64_t grad_numel = 0;
  for (const auto& p : params) grad_numel += p.numel();
  const int64_t n_params = static_cast<int64_t>(params.size()), n_terms = static_cast<int64_t>(term_names_.size());
  const bool warmup = normalisers_warming_up(*model_);
  const torch::Tensor stats_start = warmup ? normaliser_statistics(*model_) : torch::Tensor();

  // What the ranks sum, in one buffer: gradients | samples that had each parameter's
  // gradient | loss, samples | term sums | term counts | normaliser statistics added.
  const int64_t n_totals = 2 + 2 * n_terms, n_stats = warmup ? stats_start.numel() : 0;
  torch::Tensor sums = torch::zeros({grad_numel + n_params + n_totals + n_stats}, torch::kFloat64);
  torch::Tensor grads = sums.narrow(0, 0, grad_numel);
  torch::Tensor present = sums.narrow(0, grad_numel, n_params);
  torch::Tensor totals = sums.narrow(0, grad_numel + n_params, n_totals);
  torch::Tensor stats_added = sums.narrow(0, grad_numel + n_params + n_totals, n_stats);
  auto total = totals.accessor<double, 1>();
  auto present_count = present.accessor<double, 1>();
  for (int j = 0; j < batch; ++j) {
    std::mt19937_64 rng = sample_rng(config_.run.seed, step_, int64_t(rank) * batch + j);
    if (warmup) set_normaliser_statistics(*model_, stats_start);
    for (auto& p : params) p.mutable_grad() = torch::Tensor();
    lap("step set-up");
    SampleResult s = train_sample(rng, j, rollout, result.collision_weight);
    if (j == 0) {
      result.rollout = s.rollout;
      result.K = s.K;
      result.age = s.age;
    }
    int64_t offset = 0;
    for (int64_t i = 0; i < n_params; ++i) {
      const torch::Tensor& g = params[i].grad();
      if (g.defined()) {
        grads.narrow(0, offset, g.numel()).add_(g.detach().reshape({-1}).to(torch::kCPU, torch::kFloat64));
        present_count[i] += 1;
      }
      offset += params[i].numel();
    }
    total[0] += s.loss;
    total[1] += 1;
    for (const auto& [name, value] : s.terms) {
      const auto k = std::find(term_names_.begin(), term_names_.end(), name) - term_names_.begin();
      if (k == n_terms) throw Error("training: term '" + name + "' is not one of the physics terms");
      total[2 + k] += value;
      total[2 + n_terms + k] += 1;
    }
    if (warmup) stats_added.add_(normaliser_statistics(*model_) - stats_start);
    lap("gradients to the flat buffer");
  }
  if (group_) group_->all_reduce_sum(sums);
  lap("all-reduce");

  // Every rank holds the same sums now, so every rank makes the same decisions below.
  const double samples = total[1];
  result.samples = static_cast<int64_t>(samples);
  if (warmup) set_normaliser_statistics(*model_, stats_start + stats_added);
  result.loss = total[0] / samples;
  for (int64_t k = 0; k < n_terms; ++k)
    if (total[2 + n_terms + k] > 0) result.terms.emplace_back(term_names_[k], total[2 + k] / total[2 + n_terms + k]);
  const bool finite = std::isfinite(result.loss) && torch::isfinite(grads).all().item<bool>();
  int64_t offset = 0;
  for (int64_t i = 0; i < n_params; ++i) {
    auto& p = params[i];
    if (finite && present_count[i] > 0)
      p.mutable_grad() = (grads.narrow(0, offset, p.numel()) / samples).view(p.sizes()).to(p.options());
    else
      p.mutable_grad() = torch::Tensor();
    offset += p.numel();
  }
  if (!finite) {
    result.skipped = true;
    ++skipped_steps_;
  } else {
    torch::nn::utils::clip_grad_norm_(params, config_.optim.grad_clip);
    optimizer_->step();
  }
  lap("clip + Adam");
  ++step_;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  elapsed_seconds_ += result.seconds;
  return result;
}

}  // namespace pb4u

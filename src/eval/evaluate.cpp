#include "pb4u/eval/evaluate.h"

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <sstream>

#include "pb4u/data/dataset.h"
#include "pb4u/eval/frames_csv.h"
#include "pb4u/rollout/rollout.h"
#include "pb4u/rollout/settled_start.h"
#include "pb4u/scene/pins.h"
#include "pb4u/io/preview.h"
#include "pb4u/util/atomic_file.h"
#include "pb4u/util/error.h"
#include "pb4u/util/median.h"
#include "pb4u/util/number_format.h"
#include "pb4u/util/progress.h"

namespace pb4u {
namespace {

struct Sequence {
  const Body* body;
  const Garment* garment;
  const MotionRecord* motion;  // null: a body-less rollout from rest
};

std::string pretty_term(const std::string& name) {
  std::string s = name;
  if (!s.empty()) s[0] = static_cast<char>(std::toupper(s[0]));
  return s;
}

// The penetration figures, reported as rows beside the terms: JSON / CSV key, table label,
// table scale (fractions in percent) and the summary field.
struct PenetrationKey {
  const char* key;
  const char* label;
  double table_scale;
  double (*value)(const PenetrationSummary&);
};
const PenetrationKey kPenetrationKeys[] = {
    {"penetrating_fraction", "Inside %", 100.0, [](const PenetrationSummary& s) { return s.penetrating_fraction; }},
    {"max_penetrating_fraction", "Inside max %", 100.0,
     [](const PenetrationSummary& s) { return s.max_penetrating_fraction; }},
    {"max_penetration_mm", "Depth max mm", 1.0, [](const PenetrationSummary& s) { return s.max_penetration_mm; }},
    // Cloth edges through a body triangle (both ends may be outside): the most on a frame, and
    // the share of frames with any.
    {"max_edges_through", "Edges thru max", 1.0,
     [](const PenetrationSummary& s) { return double(s.max_edges_through); }},
    {"edges_through_frames", "Edges thru %", 100.0,
     [](const PenetrationSummary& s) {
       return s.frames > 0 ? double(s.frames_with_edges_through) / s.frames : 0.0;
     }},
    // The share of frames where the body crosses itself (one part inside another): there cloth
    // pinched between the parts has no intersection-free place, whatever the method.
    {"body_self_crossing_frames", "Body crosses %", 100.0,
     [](const PenetrationSummary& s) {
       return s.frames > 0 ? double(s.frames_with_body_self_crossing) / s.frames : 0.0;
     }}};

const PenetrationKey* penetration_key(const std::string& row) {
  for (const auto& k : kPenetrationKeys)
    if (row == k.key) return &k;
  return nullptr;
}

// Value of row `row` (a term, "total" or a penetration key) from a mean report and a
// penetration summary, if there is one.
std::optional<double> row_value(const std::optional<EnergyReport>& mean,
                                const std::optional<PenetrationSummary>& penetration, const std::string& row) {
  if (const PenetrationKey* k = penetration_key(row)) {
    if (!penetration) return std::nullopt;
    return k->value(*penetration);
  }
  if (!mean) return std::nullopt;
  if (row == "total") return mean->total;
  if (row == "residual_mm") return mean->residual_mm;
  if (!mean->has(row)) return std::nullopt;
  return mean->value(row);
}

std::optional<double> value_of(const MethodResult& m, const std::string& row) {
  return row_value(m.mean, m.penetration, row);
}

// A level's rows: its terms, the total and, when any method measured penetration, its keys.
std::vector<std::string> level_rows(const LevelResult& lr) {
  std::vector<std::string> rows = lr.terms;
  rows.push_back("total");
  rows.push_back("residual_mm");
  bool penetration = false;
  for (const auto& m : lr.methods) penetration = penetration || m.penetration.has_value();
  if (penetration)
    for (const auto& k : kPenetrationKeys) rows.push_back(k.key);
  return rows;
}

}  // namespace

std::vector<std::string> method_names(const std::vector<ModelFile>& models,
                                      const std::vector<std::string>& names) {
  std::vector<std::string> out;
  std::map<std::string, int> count;
  for (const auto& m : models) ++count[method_name(m.config)];
  for (size_t i = 0; i < models.size(); ++i) {
    std::string name = method_name(models[i].config);
    if (i < names.size() && !names[i].empty()) {
      name = names[i];
    } else if (count[name] > 1) {
      name += " (" + std::filesystem::path(models[i].path).stem().string() + ")";
    }
    if (std::find(out.begin(), out.end(), name) != out.end()) name += " #" + std::to_string(i + 1);
    out.push_back(name);
  }
  return out;
}

namespace {

// The sequences of one level: each body's motions of the config's split with each of its
// garments; without a body in the effects, each garment once, from rest.
std::vector<Sequence> level_sequences(const Dataset& data, const EvalConfig& config, const Effects& effects,
                                      int level) {
  const auto listed = [](const std::vector<std::string>& names, const std::string& name) {
    return names.empty() || std::find(names.begin(), names.end(), name) != names.end();
  };
  std::vector<Sequence> sequences;
  for (const auto& record : data.bodies) {
    std::vector<const MotionRecord*> motions;
    if (effects.needs_body()) {
      for (const auto& m : data.motions)
        if (m.body == record.body.name && m.split == config.split && listed(config.motions, m.name) &&
            m.motion.num_frames() > config.start_frame + 1)
          motions.push_back(&m);
      if (config.max_sequences > 0 && int(motions.size()) > config.max_sequences) motions.resize(config.max_sequences);
    } else {
      motions.push_back(nullptr);  // from rest: no motion
    }
    for (const auto& g : record.garments) {
      if (!listed(config.garments, g.name)) continue;
      for (const MotionRecord* m : motions) sequences.push_back({&record.body, &g.levels.at(level - 1), m});
    }
  }
  if (sequences.empty())
    throw Error(config.dataset + ": " +
                (effects.needs_body() ? "no motion of split '" + config.split + "' with a matching garment"
                                      : std::string("no matching garment")) +
                " at level " + std::to_string(level));
  return sequences;
}

// How many frames a sequence rolls out: the motion's from the start frame, at most max_frames;
// without a motion, max_frames.
int sequence_steps(const EvalConfig& config, const Sequence& s) {
  if (!s.motion) return config.max_frames;
  int steps = s.motion->motion.num_frames() - 1 - config.start_frame;
  if (config.max_frames > 0) steps = std::min(steps, config.max_frames);
  return steps;
}

// What one sequence rolls out: its LBS-initialised start on the motion, or without a body the
// garment still at rest, pinned by the config's rule.
RolloutInput sequence_input(const EvalConfig& config, const Effects& effects, const Sequence& s) {
  RolloutInput in;
  if (s.motion) {
    in = lbs_rollout_input(*s.body, *s.garment, s.motion->motion, config.start_frame, sequence_steps(config, s),
                           effects, config.material, config.push_out_gap);
  } else {
    in.garment_rest = s.garment->mesh;
    in.x0 = in.x_prev = s.garment->mesh.V;
    in.effects = effects;
    in.material = in.metric_material = config.material;
    in.steps = sequence_steps(config, s);
  }
  if (effects.pins) in.pinned = top_band_vertices(in.x0, config.pins.top_band);
  if (s.motion && config.waistband.holds(s.garment->name)) {
    in.effects.pins = true;
    in.pinned = top_band_vertices(s.garment->mesh.V, config.waistband.band);
    in.pin_targets = skinned_pin_targets(*s.body, *s.garment, s.motion->motion, config.start_frame, in.body,
                                         config.push_out_gap);
    hold_pins_free_of_body(in);
  }
  in.divergence = config.divergence;
  in.minimum_every = config.minimum_every;
  return in;
}

// A sequence's frame 0 and the frame before it.
struct StartState {
  Eigen::MatrixXd x0, x_prev;
};

// With start: settled, each sequence's first frame reached by the reference solver from the bind
// pose (as a scene's body.start: settled), once for every method; empty entries keep the skinned
// start.
std::vector<std::optional<StartState>> settled_starts(const EvalConfig& config, const Effects& effects,
                                                      const std::vector<Sequence>& sequences) {
  std::vector<std::optional<StartState>> starts(sequences.size());
  if (config.start != "settled") return starts;
  for (size_t i = 0; i < sequences.size(); ++i) {
    const Sequence& s = sequences[i];
    const RolloutInput in = sequence_input(config, effects, s);
    const Motion& motion = s.motion->motion;
    const Pose& first = motion.frames[size_t(config.start_frame)];
    const Pose& next = motion.frames[size_t(std::min(config.start_frame + 1, motion.num_frames() - 1))];
    // Pins that ride on the body (a waistband) follow the skinned garment while it settles.
    const std::vector<int> riding = in.pin_targets.empty() ? std::vector<int>() : in.pinned;
    const SettledStart st = settled_start(*s.body, *s.garment, first, next, config.settle_steps, config.material,
                                          riding, config.push_out_gap, config.physics);
    StartState start;
    settled_rollout_start(st, riding, riding.empty() ? st.x : in.pin_targets[0], &start.x0, &start.x_prev);
    spdlog::info("{} on {}: {}", s.garment->name, s.motion->name, describe_settled_start(st, config.settle_steps));
    starts[i] = std::move(start);
  }
  return starts;
}

SequenceResult sequence_result(const Sequence& s, const RolloutResult& r) {
  SequenceResult q;
  q.body = s.body->name;
  q.garment = s.garment->name;
  q.motion = s.motion ? s.motion->name : "rest";
  q.frames = int(r.reports.size());
  q.diverged = r.diverged;
  q.diverged_at_frame = r.diverged_at_frame;
  q.diverged_reason = r.diverged_reason;
  if (r.reports.empty()) {
    q.positive_energy = q.max_positive_energy = NAN;
    return q;
  }
  q.mean = mean_report(r.reports);
  q.positive_energy = positive_energy(*q.mean);
  q.max_positive_energy = positive_energy_range(r.reports).max;
  q.median_residual_mm = median_residual_mm(r.reports);
  q.minimum = summarize_minimum(r.reports);
  if (!r.penetration.empty()) q.penetration = summarize_penetration(r.penetration);
  return q;
}

}  // namespace

std::vector<LevelResult> evaluate(const EvalConfig& config, const std::vector<EvalMethod>& methods) {
  if (methods.empty()) throw Error("evaluate: no method to evaluate (give --checkpoint or --method reference)");
  const Effects effects = Effects::from_names(config.effects, "effects");
  if (config.levels.empty()) throw Error("levels: no level to evaluate");
  if (!config.frames_dir.empty()) ensure_output_dir(config.frames_dir);  // fails before the rollouts
  if (effects.pins && config.pins.top_band <= 0)
    throw Error("pins.top_band: effect 'pins' is on but no vertex is pinned (set pins.top_band, m)");
  if (!effects.needs_body() && config.max_frames <= 0)
    throw Error("max_frames: without a body (no collision or friction among the effects) each garment starts "
                "at rest and the rollout length must be set (max_frames > 0)");
  if (config.start == "settled" && !effects.needs_body())
    throw Error("start: settled moves the garment with a body from its bind pose; without a body (no collision or "
                "friction among the effects) every garment starts at rest");
  if (!effects.needs_body() && !config.motions.empty())
    throw Error("motions: without a body each garment hangs from rest and follows no motion (leave motions empty)");
  const Dataset data = read_dataset(config.dataset);
  for (const std::string& name : config.motions)
    if (std::none_of(data.motions.begin(), data.motions.end(),
                     [&](const MotionRecord& m) { return m.name == name && m.split == config.split; }))
      throw Error(config.dataset + ": motions: '" + name + "' is not a motion of split '" + config.split + "'");
  std::vector<LevelResult> results;
  // The worst sequence of the first network method, for config.preview.
  const EvalMethod* previewed = nullptr;
  for (const EvalMethod& m : methods)
    if (m.model && !previewed) previewed = &m;
  struct Worst {
    double positive = -1;
    std::string title;
    std::vector<Eigen::MatrixXd> garment, body;
    Eigen::MatrixXi garment_faces, body_faces;
  } worst;
  for (int level : config.levels) {
    if (level < 1 || level > int(data.level_triangles.size()))
      throw Error("levels: level " + std::to_string(level) + " is not in " + config.dataset + " (it has " +
                  std::to_string(data.level_triangles.size()) + " levels)");
    const std::vector<Sequence> sequences = level_sequences(data, config, effects, level);
    const std::vector<std::optional<StartState>> starts = settled_starts(config, effects, sequences);

    LevelResult lr;
    lr.level = level;
    std::vector<const Garment*> seen;
    for (const auto& s : sequences)
      if (std::find(seen.begin(), seen.end(), s.garment) == seen.end()) seen.push_back(s.garment);
    for (const Garment* g : seen) {
      lr.triangles += g->mesh.F.rows();
      lr.vertices += g->mesh.V.rows();
    }
    lr.triangles /= int64_t(seen.size());
    lr.vertices /= int64_t(seen.size());

    // Frames, not sequences: a solver's sequence can take an hour.
    int64_t level_frames = 0;
    for (const Sequence& s : sequences) level_frames += std::max(sequence_steps(config, s), 0);
    Progress bar("evaluate Lv." + std::to_string(level), std::max<int64_t>(level_frames * int64_t(methods.size()), 1), "frame");
    for (const EvalMethod& method : methods) {
      MethodResult mr;
      mr.name = method.name;
      std::vector<EnergyReport> sequence_means;
      std::vector<PenetrationSummary> sequence_penetration;
      PhysicsConfig physics = config.physics;  // the solver's contact as the method names it
      if (!method.model && !method.solver_contact.empty()) physics.solver.contact = method.solver_contact;
      auto t0 = std::chrono::steady_clock::now();
      std::vector<double> step_ms;  // every frame's contact query + step
      std::vector<double> residual_mm;  // every frame's residual where measured
      std::vector<EnergyReport> sampled;  // every frame sampled for its minimum
      for (size_t si = 0; si < sequences.size(); ++si) {
        const Sequence& s = sequences[si];
        const Garment& garment = *s.garment;
        RolloutInput in = sequence_input(config, effects, s);
        if (starts[si]) {
          in.x0 = starts[si]->x0;
          in.x_prev = starts[si]->x_prev;
        }
        GarmentTopology topology;
        StepFunction step;
        auto step_log = std::make_shared<ContactStepLog>();
        in.step_log = step_log;
        if (method.model) {
          topology = build_garment_topology(garment.mesh, garment.name,
                                            method.model->config.graph_options().geodesic_anchors);
          step = network_stepper(*method.model, topology, -1, step_log, config.physics.solver, config.refine);
          if (config.refine.enabled()) step = refined_stepper(step, config.physics.solver, config.refine, step_log);
          if (mr.K == 0) mr.K = method.model->model->propagation_steps_for(topology.mean_edge_length);
        } else {
          step = reference_stepper(physics.solver, step_log);
        }
        const bool keep_frames = !config.preview.empty() && &method == previewed;
        std::vector<Eigen::MatrixXd> frames;
        if (keep_frames) frames.push_back(in.x0);
        // With --frames-dir, the barrier solve's account of each frame (as a scene's energies.csv),
        // where the steps are solves: the solver's, or a network's refined by the config or its file.
        const PhysicsConfig measured = physics_measured_for(physics, method.model, config.refine.enabled());
        const bool solves = !method.model || config.refine.enabled() || method.model->config.refines();
        const bool keep_logs = !config.frames_dir.empty() && solves && measured.solver.contact == "barrier" &&
                               in.effects.collision && !in.body.empty();
        std::vector<ContactStepLog> logs;
        int64_t frames_done = 0;
        const std::string status = mr.name + ", " + s.garment->name + (s.motion ? " on " + s.motion->name : "");
        FrameCallback on_frame = [&](int, const Eigen::MatrixXd& x, const EnergyReport&, const PenetrationFigures*) {
          if (keep_frames) frames.push_back(x);
          if (keep_logs) logs.push_back(*step_log);
          ++frames_done;
          bar.step(1, status);
        };
        RolloutResult r = run_rollout(in, step, measured, on_frame);
        for (size_t f = 0; f < r.step_ms.size() && f < r.contact_ms.size(); ++f)
          step_ms.push_back(r.step_ms[f] + r.contact_ms[f]);
        const std::vector<double> measured_mm = measured_residuals_mm(r.reports);
        residual_mm.insert(residual_mm.end(), measured_mm.begin(), measured_mm.end());
        for (const EnergyReport& e : r.reports)
          if (std::isfinite(e.minimum_distance_mm)) sampled.push_back(e);
        bar.step(std::max<int64_t>(in.steps - frames_done, 0), status);  // a rollout the guard stopped
        SequenceResult q = sequence_result(s, r);
        if (!config.frames_dir.empty())
          write_frames_csv(config.frames_dir + "/lv" + std::to_string(level) + "/" + file_name_from(method.name) + "/" +
                               file_name_from(q.garment + "_" + q.motion + "_" + q.body) + ".csv",
                           r, keep_logs ? &logs : nullptr);
        if (keep_frames && std::isfinite(q.positive_energy) && q.positive_energy > worst.positive) {
          worst.positive = q.positive_energy;
          char title[256];
          std::snprintf(title, sizeof title, "%s, Lv.%d %s on %s: worst sequence (positive energy mean %.3g J)%s",
                        method.name.c_str(), level, q.garment.c_str(), q.motion.c_str(), q.positive_energy,
                        q.diverged ? (", diverged at frame " + std::to_string(q.diverged_at_frame)).c_str() : "");
          worst.title = title;
          worst.garment = std::move(frames);
          worst.garment_faces = garment.mesh.F;
          worst.body.assign(in.body.begin(), in.body.begin() + std::min(in.body.size(), worst.garment.size()));
          worst.body_faces = in.body.empty() ? Eigen::MatrixXi() : in.body_faces;
        }
        if (q.diverged && (!mr.diverged || q.diverged_at_frame < mr.diverged_at_frame)) {
          mr.diverged = true;
          mr.diverged_at_frame = q.diverged_at_frame;
          mr.diverged_sequence = q.garment + "/" + q.motion;
          mr.diverged_reason = q.diverged_reason;
        }
        if (q.mean) {
          sequence_means.push_back(*q.mean);
          mr.frames += q.frames;
          ++mr.sequences;
        }
        if (q.penetration) sequence_penetration.push_back(*q.penetration);
        mr.per_sequence.push_back(std::move(q));
      }
      mr.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      mr.step_ms = median(step_ms);
      mr.median_residual_mm = median(residual_mm);
      mr.minimum = summarize_minimum(sampled);
      if (!sequence_means.empty()) mr.mean = mean_report(sequence_means);
      if (!sequence_penetration.empty()) mr.penetration = summarize_penetration(sequence_penetration);
      if (lr.K == 0 && method.model && method.model->config.is_pb4u()) lr.K = mr.K;
      lr.methods.push_back(std::move(mr));
    }
    bar.finish();
    for (const auto& t : build_terms(effects, config.physics)) lr.terms.push_back(t->name());
    results.push_back(std::move(lr));
  }
  if (!config.preview.empty() && worst.positive >= 0 &&
      write_preview(config.preview, preview_frames(int(worst.garment.size())), worst.garment, worst.garment_faces,
                    worst.body, worst.body_faces, worst.title))
    spdlog::info("wrote {} ({})", config.preview, worst.title);
  return results;
}

std::string format_table(const std::vector<LevelResult>& levels) {
  std::ostringstream out;
  bool any_penetration = false, any_minimum = false;
  for (const auto& lr : levels) {
    out << "Lv." << lr.level << "  (" << lr.triangles << " triangles, " << lr.vertices << " vertices, K = "
        << lr.K << ")\n";
    const std::vector<std::string> rows = level_rows(lr);
    size_t w0 = 14;
    std::vector<size_t> widths;
    for (const auto& m : lr.methods) widths.push_back(std::max<size_t>(m.name.size(), 10) + 2);
    out << std::string(w0, ' ');
    for (size_t i = 0; i < lr.methods.size(); ++i) {
      std::string h = lr.methods[i].name;
      out << std::string(widths[i] - h.size(), ' ') << h;
    }
    out << "\n";
    for (const auto& row : rows) {
      const PenetrationKey* pk = penetration_key(row);
      any_penetration = any_penetration || pk;
      std::string label = pk ? pk->label : row == "residual_mm" ? "Residual mm" : pretty_term(row);
      out << label << std::string(w0 - std::min(w0, label.size()), ' ');
      std::optional<double> best;
      for (const auto& m : lr.methods) {
        auto v = value_of(m, row);
        if (v && (!best || *v < *best)) best = v;
      }
      for (size_t i = 0; i < lr.methods.size(); ++i) {
        auto v = value_of(lr.methods[i], row);
        std::string cell = !v ? "n/a" : pk ? fixed(*v * pk->table_scale, 2) : scientific(*v, 2);
        if (v && lr.methods.size() > 1 && *v == *best) cell += "*";
        else cell += " ";
        out << std::string(widths[i] - std::min(widths[i], cell.size()), ' ') << cell;
      }
      out << "\n";
    }
    out << "Step ms" << std::string(w0 - 7, ' ');
    for (size_t i = 0; i < lr.methods.size(); ++i) {
      const double ms = lr.methods[i].step_ms;
      const std::string cell = std::isfinite(ms) ? fixed(ms, 1) + " " : "n/a ";
      out << std::string(widths[i] - std::min(widths[i], cell.size()), ' ') << cell;
    }
    out << "\n";
    bool sampled = false;
    for (const auto& m : lr.methods) sampled = sampled || m.minimum.frames > 0;
    if (sampled) {
      any_minimum = true;
      const std::pair<const char*, double MinimumSummary::*> minimum_rows[] = {
          {"To min. mm", &MinimumSummary::distance_median_mm},
          {"To min. max", &MinimumSummary::distance_max_mm},
          {"Gap to min. J", &MinimumSummary::gap_median_j}};
      for (const auto& [label, field] : minimum_rows) {
        out << label << std::string(w0 - std::min(w0, std::strlen(label)), ' ');
        for (size_t i = 0; i < lr.methods.size(); ++i) {
          const double v = lr.methods[i].minimum.*field;
          const std::string cell = !std::isfinite(v) ? "n/a " : field == &MinimumSummary::gap_median_j
                                                                    ? scientific(v, 2) + " "
                                                                    : fixed(v, 2) + " ";
          out << std::string(widths[i] - std::min(widths[i], cell.size()), ' ') << cell;
        }
        out << "\n";
      }
    }
    for (const auto& m : lr.methods) {
      if (m.diverged)
        out << "  " << m.name << ": diverged at frame " << m.diverged_at_frame << " (" << m.diverged_sequence
            << ": " << m.diverged_reason << "); averages use the " << m.frames << " frames before the stop\n";
    }
    out << "\n";
  }
  out << "* lowest value in the row. Energies in J, per frame, averaged over frames and sequences. Step ms: the\n"
         "median over frames of one step's wall time (body contact query and step, measuring not included).\n";
  if (any_minimum)
    out << "To min.: on the frames sampled with minimum_every, the largest vertex move from the step to the\n"
           "energy's minimum the solver reaches from it (mm; median over the frames, and max); Gap to min. J:\n"
           "how much lower the energy is there (median).\n";
  if (any_penetration)
    out << "Inside %: garment vertices inside the body, mean over frames and sequences (max: worst frame);\n"
           "Depth max mm: the deepest garment vertex on any frame; Edges thru: cloth edges through a body\n"
           "triangle (both ends may be outside), the most on a frame (max) and the share of frames with any (%);\n"
           "Body crosses %: the share of frames on which one part of the body lies inside another (cloth pinched\n"
           "there has no free place).\n";
  return out.str();
}

namespace {

// A CSV value: 9 significant digits ("%.9g"); non-finite values are "null", as in the JSON.
std::string eval_csv_number(double v) { return significant(v, 9, "null"); }

}  // namespace

std::string format_csv(const std::vector<LevelResult>& levels) {
  std::ostringstream out;
  out << "level,triangles,vertices,method,K,term,value,diverged,diverged_at_frame\n";
  for (const auto& lr : levels)
    for (const auto& m : lr.methods) {
      std::string name = m.name;
      if (name.find(',') != std::string::npos) name = "\"" + name + "\"";
      auto line = [&](const std::string& row, std::optional<double> v) {
        out << lr.level << "," << lr.triangles << "," << lr.vertices << "," << name << "," << m.K << "," << row
            << "," << (v ? eval_csv_number(*v) : "") << "," << (m.diverged ? "true" : "false") << ","
            << (m.diverged ? std::to_string(m.diverged_at_frame) : "") << "\n";
      };
      for (const auto& row : level_rows(lr)) line(row, value_of(m, row));
      line("step_ms", std::isfinite(m.step_ms) ? std::optional<double>(m.step_ms) : std::nullopt);
      if (m.minimum.frames > 0) {
        line("distance_to_minimum_mm_median", m.minimum.distance_median_mm);
        line("distance_to_minimum_mm_max", m.minimum.distance_max_mm);
        line("energy_gap_j_median", m.minimum.gap_median_j);
      }
    }
  return out.str();
}

namespace {

using EvalJson = nlohmann::ordered_json;  // keys in the order written

// A figure as JSON: rounded to 9 significant digits (what "%.9g" printed), so the shortest
// round-trip form nlohmann writes has the same digits; non-finite values are null.
EvalJson eval_json_figure(double v) {
  return std::isfinite(v) ? EvalJson(round_to_significant(v, 9)) : EvalJson(nullptr);
}

// "<row>": value for each row (null when absent); a sequence without a measured frame has
// no penetration keys.
void eval_add_rows(EvalJson& out, const std::vector<std::string>& rows,
                   const std::optional<EnergyReport>& mean,
                   const std::optional<PenetrationSummary>& penetration) {
  for (const auto& row : rows) {
    if (penetration_key(row) && !penetration) continue;
    auto v = row_value(mean, penetration, row);
    out[row] = v ? eval_json_figure(*v) : EvalJson(nullptr);
  }
}

// The divergence keys (SPEC 7), and the reason when it diverged.
void eval_add_divergence(EvalJson& out, bool diverged, int at_frame, const std::string& reason) {
  out["diverged"] = diverged;
  out["diverged_at_frame"] = diverged ? EvalJson(at_frame) : EvalJson(nullptr);
  if (diverged) out["diverged_reason"] = reason;
}

// With frames sampled for their minimum (minimum_every): "distance_to_minimum": how many, the
// median and largest distance (mm) and the median energy gap (J).
void eval_add_minimum(EvalJson& out, const MinimumSummary& minimum) {
  if (minimum.frames == 0) return;
  out["distance_to_minimum"] = {{"frames", minimum.frames},
                                {"median_mm", eval_json_figure(minimum.distance_median_mm)},
                                {"max_mm", eval_json_figure(minimum.distance_max_mm)},
                                {"median_energy_gap_j", eval_json_figure(minimum.gap_median_j)}};
}

EvalJson eval_json_sequence(const SequenceResult& q, const std::vector<std::string>& rows) {
  EvalJson out = EvalJson::object();
  out["body"] = q.body;
  out["garment"] = q.garment;
  out["motion"] = q.motion;
  out["frames"] = q.frames;
  eval_add_rows(out, rows, q.mean, q.penetration);
  out["positive_energy"] = eval_json_figure(q.positive_energy);
  out["max_positive_energy"] = eval_json_figure(q.max_positive_energy);
  out["median_residual_mm"] = eval_json_figure(q.median_residual_mm);
  eval_add_minimum(out, q.minimum);
  eval_add_divergence(out, q.diverged, q.diverged_at_frame, q.diverged_reason);
  return out;
}

}  // namespace

std::string format_json(const std::vector<LevelResult>& levels) {
  EvalJson out = {{"levels", EvalJson::array()}};
  for (const auto& lr : levels) {
    EvalJson level = {
        {"level", lr.level}, {"triangles", lr.triangles}, {"vertices", lr.vertices}, {"K", lr.K}};
    EvalJson& methods = level["methods"] = EvalJson::object();
    const std::vector<std::string> rows = level_rows(lr);
    for (const auto& m : lr.methods) {
      EvalJson method = EvalJson::object();
      eval_add_rows(method, rows, m.mean, m.penetration);
      EvalJson& sequences = method["sequences"] = EvalJson::array();
      for (const auto& q : m.per_sequence) sequences.push_back(eval_json_sequence(q, rows));
      method["K"] = m.K;
      method["frames"] = m.frames;
      method["step_ms"] = eval_json_figure(m.step_ms);
      method["median_residual_mm"] = eval_json_figure(m.median_residual_mm);
      eval_add_minimum(method, m.minimum);
      eval_add_divergence(method, m.diverged, m.diverged_at_frame, m.diverged_reason);
      methods[m.name] = std::move(method);
    }
    out["levels"].push_back(std::move(level));
  }
  // One line; bytes that are not UTF-8 (a file name) become U+FFFD rather than an exception.
  return out.dump(-1, ' ', false, EvalJson::error_handler_t::replace) + "\n";
}

}  // namespace pb4u

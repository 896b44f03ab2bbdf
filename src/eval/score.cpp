#include "pb4u/eval/score.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <sstream>

#include "pb4u/rollout/rollout.h"
#include "pb4u/util/eigen_tensor.h"
#include "pb4u/util/error.h"
#include "pb4u/util/number_format.h"

namespace pb4u {

namespace {

std::vector<std::string> columns(const ScoreResult& r) {
  std::vector<std::string> names;
  if (!r.reports.empty())
    for (const auto& t : r.reports[0].terms) names.push_back(t.first);
  names.push_back("total");
  names.push_back("residual_mm");
  if (!r.penetration.empty()) {
    names.push_back("penetrating_fraction");
    names.push_back("max_penetration_mm");
    names.push_back("edges_through_body");
    names.push_back("body_self_crossing_faces");
  }
  return names;
}

std::vector<double> row(const ScoreResult& r, size_t i) {
  std::vector<double> v;
  for (const auto& t : r.reports[i].terms) v.push_back(t.second);
  v.push_back(r.reports[i].total);
  v.push_back(r.reports[i].residual_mm);
  if (!r.penetration.empty()) {
    v.push_back(r.penetration[i].penetrating_fraction);
    v.push_back(r.penetration[i].max_penetration_mm);
    v.push_back(r.penetration[i].edges_through);
    v.push_back(r.penetration[i].body_self_crossing_faces);
  }
  return v;
}

std::string g9(double v) {
  char s[32];
  std::snprintf(s, sizeof s, "%.9g", v);
  return s;
}

}  // namespace

ScoreResult score_sequence(const ScoreInput& in) {
  const Eigen::Index n = in.garment_rest.V.rows();
  const int T = static_cast<int>(in.frames.size());
  if (T < 2) throw Error("score: " + std::to_string(T) + " frame(s) given; at least 2 are needed (frame 0 is the start)");
  for (int t = 0; t < T; ++t)
    if (in.frames[t].rows() != n || in.frames[t].cols() != 3)
      throw Error("score: frame " + std::to_string(t) + " has " + std::to_string(in.frames[t].rows()) +
                  " vertices, the rest mesh " + std::to_string(n));
  if (in.previous.size() && in.previous.rows() != n)
    throw Error("score: the previous frame has " + std::to_string(in.previous.rows()) + " vertices, the rest mesh " +
                std::to_string(n));
  if (!in.body.empty() && int(in.body.size()) != T)
    throw Error("score: " + std::to_string(in.body.size()) + " body frames for " + std::to_string(T) +
                " garment frames (one body frame per garment frame is needed)");
  if (in.effects.needs_body() && in.body.empty())
    throw Error("score: collision and friction need a body (give its frames, or drop those effects)");
  const Eigen::Index body_vertices = in.body_faces.size() ? in.body_faces.maxCoeff() + 1 : 0;
  for (size_t t = 0; t < in.body.size(); ++t)
    if (in.body[t].rows() != in.body[0].rows() || in.body[t].rows() < body_vertices)
      throw Error("score: body frame " + std::to_string(t) + " does not match the body mesh (" +
                  std::to_string(in.body[t].rows()) + " vertices)");

  RolloutInput rollout;
  rollout.garment_rest = in.garment_rest;
  rollout.x0 = in.frames[0];
  rollout.x_prev = in.previous.size() ? in.previous : in.frames[0];
  rollout.body = in.body;
  rollout.body_faces = in.body_faces;
  rollout.effects = in.effects;
  rollout.effects.pins = false;  // pins constrain a stepper; the recorded frames already obey them
  rollout.material = in.material;
  rollout.metric_material = in.material;
  rollout.steps = T - 1;
  rollout.dt = in.dt;
  rollout.divergence.energy_ratio = 0;  // a score measures what it is given, whatever it is

  // The "stepper" replays the recorded frames, so the energies are run_rollout's own.
  auto next = std::make_shared<int>(1);
  const std::vector<Eigen::MatrixXd>* frames = &in.frames;
  StepFunction replay = [next, frames](const FrameState&, const ClothGeometry&, const TermList&,
                                       const BodyContact*) { return matrix_to_tensor((*frames)[(*next)++]); };
  RolloutResult r = run_rollout(rollout, replay, in.physics);

  ScoreResult result;
  result.frames = T;
  result.reports = r.reports;
  result.penetration = r.penetration;
  if (r.diverged) result.nonfinite_at_frame = r.diverged_at_frame;
  if (!result.reports.empty()) {
    result.mean = mean_report(result.reports);
    const PositiveEnergyRange positive = positive_energy_range(result.reports);
    result.positive_mean = positive.mean;
    result.positive_max = positive.max;
  }
  if (!result.penetration.empty()) result.penetration_summary = summarize_penetration(result.penetration);
  return result;
}

std::string score_csv(const ScoreResult& r) {
  std::ostringstream out;
  const auto names = columns(r);
  out << "frame";
  for (const auto& c : names) out << ',' << c;
  out << "\n0";
  for (size_t k = 0; k < names.size(); ++k) out << ",nan";
  out << '\n';
  for (size_t i = 0; i < r.reports.size(); ++i) {
    out << i + 1;
    for (double v : row(r, i)) out << ',' << g9(v);
    out << '\n';
  }
  return out.str();
}

std::string score_json(const ScoreResult& r) {
  using Json = nlohmann::ordered_json;  // keys in the order written
  // A figure rounded to the 9 significant digits of the CSV (g9), so nlohmann's shortest
  // round-trip form has the same digits; non-finite values are null.
  auto figure = [](double v) {
    return std::isfinite(v) ? Json(round_to_significant(v, 9)) : Json(nullptr);
  };
  Json out = {{"frames", r.frames}, {"scored_frames", r.reports.size()}};
  Json& mean = out["mean"] = Json::object();
  for (const auto& t : r.mean.terms) mean[t.first] = figure(t.second);
  mean["total"] = figure(r.reports.empty() ? NAN : r.mean.total);
  mean["residual_mm"] = figure(r.reports.empty() ? NAN : r.mean.residual_mm);
  out["positive_mean"] = figure(r.positive_mean);
  out["positive_max"] = figure(r.positive_max);
  if (!r.penetration.empty()) {
    out["penetrating_fraction"] = figure(r.penetration_summary.penetrating_fraction);
    out["max_penetrating_fraction"] = figure(r.penetration_summary.max_penetrating_fraction);
    out["max_penetration_mm"] = figure(r.penetration_summary.max_penetration_mm);
    out["max_edges_through_body"] = r.penetration_summary.max_edges_through;
    out["frames_with_edges_through_body"] = r.penetration_summary.frames_with_edges_through;
    out["frames_with_body_self_crossing"] = r.penetration_summary.frames_with_body_self_crossing;
    out["max_body_self_crossing_faces"] = r.penetration_summary.max_body_self_crossing_faces;
  }
  out["nonfinite_at_frame"] = r.nonfinite_at_frame < 0 ? Json(nullptr) : Json(r.nonfinite_at_frame);
  Json& per_frame = out["per_frame"] = Json::array();
  const auto names = columns(r);
  for (size_t i = 0; i < r.reports.size(); ++i) {
    Json frame = {{"frame", i + 1}};
    const auto v = row(r, i);
    for (size_t k = 0; k < names.size(); ++k) frame[names[k]] = figure(v[k]);
    per_frame.push_back(std::move(frame));
  }
  // One line; bytes that are not UTF-8 become U+FFFD rather than an exception.
  return out.dump(-1, ' ', false, Json::error_handler_t::replace) + "\n";
}

std::string score_table(const ScoreResult& r, const std::string& title) {
  std::ostringstream out;
  char line[160];
  out << title << ": " << r.frames << " frames, " << r.reports.size() << " scored (frame 0 is the start)\n";
  if (r.nonfinite_at_frame >= 0)
    out << "  frame " << r.nonfinite_at_frame << " is not finite: the figures stop before it\n";
  std::snprintf(line, sizeof line, "  %-22s %14s %14s\n", "term", "mean J/frame", "max J/frame");
  out << line;
  for (size_t k = 0; k < r.mean.terms.size(); ++k) {
    double mx = -std::numeric_limits<double>::infinity();
    for (const auto& rep : r.reports) mx = std::max(mx, rep.terms[k].second);
    std::snprintf(line, sizeof line, "  %-22s %14.6g %14.6g\n", r.mean.terms[k].first.c_str(), r.mean.terms[k].second, mx);
    out << line;
  }
  double total_max = -std::numeric_limits<double>::infinity();
  for (const auto& rep : r.reports) total_max = std::max(total_max, rep.total);
  std::snprintf(line, sizeof line, "  %-22s %14.6g %14.6g\n", "total", r.mean.total, total_max);
  out << line;
  std::snprintf(line, sizeof line, "  %-22s %14.6g %14.6g\n", "positive (s+b+c)", r.positive_mean, r.positive_max);
  out << line;
  double residual_max = -std::numeric_limits<double>::infinity();
  for (const auto& rep : r.reports) residual_max = std::max(residual_max, rep.residual_mm);
  std::snprintf(line, sizeof line, "  %-22s %14.6g %14.6g\n", "residual (mm)", r.mean.residual_mm, residual_max);
  out << line;
  if (!r.penetration.empty()) {
    std::snprintf(line, sizeof line,
                  "  inside the body: mean %.2f%%, max %.2f%% of vertices; deepest %.2f mm; cloth edges through it on "
                  "%d frames (at most %d)\n",
                  100 * r.penetration_summary.penetrating_fraction,
                  100 * r.penetration_summary.max_penetrating_fraction, r.penetration_summary.max_penetration_mm,
                  r.penetration_summary.frames_with_edges_through, r.penetration_summary.max_edges_through);
    out << line;
  }
  return out.str();
}

}  // namespace pb4u

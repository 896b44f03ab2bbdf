#include "pb4u/eval/evaluate.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include "pb4u/data/dataset.h"
#include "pb4u/eval/rollout.h"
#include "pb4u/util/error.h"
#include "pb4u/util/progress.h"

namespace pb4u {
namespace {

struct Sequence {
  const Body* body;
  const Garment* garment;
  const MotionRecord* motion;
};

std::string pretty_term(const std::string& name) {
  std::string s = name;
  if (!s.empty()) s[0] = static_cast<char>(std::toupper(s[0]));
  return s;
}

std::string sci(double v) {
  char s[32];
  std::snprintf(s, sizeof s, "%.2E", v);
  return s;
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      char e[8];
      std::snprintf(e, sizeof e, "\\u%04x", c);
      out += e;
      continue;
    }
    out += c;
  }
  return out + "\"";
}

std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  char s[32];
  std::snprintf(s, sizeof s, "%.9g", v);
  return s;
}

// Value of `term` ("total" included) for a method, if it has finite frames.
std::optional<double> value_of(const MethodResult& m, const std::string& term) {
  if (!m.mean) return std::nullopt;
  if (term == "total") return m.mean->total;
  if (!m.mean->has(term)) return std::nullopt;
  return m.mean->value(term);
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

std::vector<LevelResult> evaluate(const EvalConfig& config, const std::vector<EvalMethod>& methods) {
  if (methods.empty()) throw Error("evaluate: no method to evaluate (give --checkpoint or --method reference)");
  const Dataset data = read_dataset(config.dataset);
  const Effects effects = Effects::from_names(config.effects, "effects");
  if (config.levels.empty()) throw Error("levels: no level to evaluate");
  std::vector<LevelResult> results;
  for (int level : config.levels) {
    if (level < 1 || level > int(data.level_triangles.size()))
      throw Error("levels: level " + std::to_string(level) + " is not in " + config.dataset + " (it has " +
                  std::to_string(data.level_triangles.size()) + " levels)");
    std::vector<Sequence> sequences;
    for (const auto& record : data.bodies) {
      std::vector<const MotionRecord*> test;
      for (const auto& m : data.motions)
        if (m.body == record.body.name && m.split == "test" && m.motion.num_frames() > config.start_frame + 1)
          test.push_back(&m);
      if (config.max_sequences > 0 && int(test.size()) > config.max_sequences) test.resize(config.max_sequences);
      for (const auto& g : record.garments) {
        if (!config.garments.empty() &&
            std::find(config.garments.begin(), config.garments.end(), g.name) == config.garments.end())
          continue;
        for (const MotionRecord* m : test) sequences.push_back({&record.body, &g.levels.at(level - 1), m});
      }
    }
    if (sequences.empty())
      throw Error(config.dataset + ": no test-split motion with a matching garment at level " + std::to_string(level));

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

    Progress bar("Lv." + std::to_string(level), int64_t(sequences.size() * methods.size()), "seq");
    for (const EvalMethod& method : methods) {
      MethodResult mr;
      mr.name = method.name;
      std::vector<EnergyReport> sequence_means;
      auto t0 = std::chrono::steady_clock::now();
      for (const Sequence& s : sequences) {
        const Garment& garment = *s.garment;
        const Motion& motion = s.motion->motion;
        const int start = config.start_frame;
        int steps = motion.num_frames() - 1 - start;
        if (config.max_frames > 0) steps = std::min(steps, config.max_frames);
        RolloutInput in = lbs_rollout_input(*s.body, garment, motion, start, steps, effects, config.material,
                                            config.push_out_gap);
        GarmentTopology topology;
        StepFunction step;
        if (method.model) {
          topology = build_garment_topology(garment.mesh, garment.name);
          step = network_stepper(*method.model, topology);
          if (mr.K == 0) mr.K = method.model->model->propagation_steps_for(topology.mean_edge_length);
        } else {
          step = reference_stepper(config.physics.solver);
        }
        RolloutResult r = run_rollout(in, step, config.physics);
        if (r.diverged && (!mr.diverged || r.diverged_at_frame < mr.diverged_at_frame)) {
          mr.diverged = true;
          mr.diverged_at_frame = r.diverged_at_frame;
          mr.diverged_sequence = garment.name + "/" + s.motion->name;
        }
        if (!r.reports.empty()) {
          sequence_means.push_back(mean_report(r.reports));
          mr.frames += int(r.reports.size());
          ++mr.sequences;
        }
        bar.step(1, mr.name);
      }
      mr.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (!sequence_means.empty()) mr.mean = mean_report(sequence_means);
      if (lr.K == 0 && method.model && method.model->config.is_pb4u()) lr.K = mr.K;
      lr.methods.push_back(std::move(mr));
    }
    bar.finish();
    for (const auto& t : build_terms(effects, config.physics)) lr.terms.push_back(t->name());
    results.push_back(std::move(lr));
  }
  return results;
}

std::string format_table(const std::vector<LevelResult>& levels) {
  std::ostringstream out;
  for (const auto& lr : levels) {
    out << "Lv." << lr.level << "  (" << lr.triangles << " triangles, " << lr.vertices << " vertices, K = "
        << lr.K << ")\n";
    std::vector<std::string> rows = lr.terms;
    rows.push_back("total");
    size_t w0 = 10;
    std::vector<size_t> widths;
    for (const auto& m : lr.methods) widths.push_back(std::max<size_t>(m.name.size(), 10) + 2);
    out << std::string(w0, ' ');
    for (size_t i = 0; i < lr.methods.size(); ++i) {
      std::string h = lr.methods[i].name;
      out << std::string(widths[i] - h.size(), ' ') << h;
    }
    out << "\n";
    for (const auto& row : rows) {
      std::string label = pretty_term(row);
      out << label << std::string(w0 - std::min(w0, label.size()), ' ');
      std::optional<double> best;
      for (const auto& m : lr.methods) {
        auto v = value_of(m, row);
        if (v && (!best || *v < *best)) best = v;
      }
      for (size_t i = 0; i < lr.methods.size(); ++i) {
        auto v = value_of(lr.methods[i], row);
        std::string cell = v ? sci(*v) : "n/a";
        if (v && lr.methods.size() > 1 && *v == *best) cell += "*";
        else cell += " ";
        out << std::string(widths[i] - std::min(widths[i], cell.size()), ' ') << cell;
      }
      out << "\n";
    }
    for (const auto& m : lr.methods) {
      if (m.diverged)
        out << "  " << m.name << ": diverged at frame " << m.diverged_at_frame << " (" << m.diverged_sequence
            << "); averages use the " << m.frames << " finite frames\n";
    }
    out << "\n";
  }
  out << "* lowest value in the row. Energies in J, per frame, averaged over frames and sequences.\n";
  return out.str();
}

std::string format_csv(const std::vector<LevelResult>& levels) {
  std::ostringstream out;
  out << "level,triangles,vertices,method,K,term,value,diverged,diverged_at_frame\n";
  for (const auto& lr : levels)
    for (const auto& m : lr.methods) {
      std::vector<std::string> rows = lr.terms;
      rows.push_back("total");
      for (const auto& row : rows) {
        auto v = value_of(m, row);
        std::string name = m.name;
        if (name.find(',') != std::string::npos) name = "\"" + name + "\"";
        out << lr.level << "," << lr.triangles << "," << lr.vertices << "," << name << "," << m.K << "," << row
            << "," << (v ? json_number(*v) : "") << "," << (m.diverged ? "true" : "false") << ","
            << (m.diverged ? std::to_string(m.diverged_at_frame) : "") << "\n";
      }
    }
  return out.str();
}

std::string format_json(const std::vector<LevelResult>& levels) {
  std::ostringstream out;
  out << "{\"levels\": [";
  for (size_t l = 0; l < levels.size(); ++l) {
    const auto& lr = levels[l];
    out << (l ? ", " : "") << "{\"level\": " << lr.level << ", \"triangles\": " << lr.triangles
        << ", \"vertices\": " << lr.vertices << ", \"K\": " << lr.K << ", \"methods\": {";
    for (size_t i = 0; i < lr.methods.size(); ++i) {
      const auto& m = lr.methods[i];
      out << (i ? ", " : "") << json_string(m.name) << ": {";
      std::vector<std::string> rows = lr.terms;
      rows.push_back("total");
      for (const auto& row : rows) {
        auto v = value_of(m, row);
        out << json_string(row) << ": " << (v ? json_number(*v) : "null") << ", ";
      }
      out << "\"K\": " << m.K << ", \"frames\": " << m.frames << ", \"diverged\": " << (m.diverged ? "true" : "false")
          << ", \"diverged_at_frame\": " << (m.diverged ? std::to_string(m.diverged_at_frame) : "null") << "}";
    }
    out << "}}";
  }
  out << "]}\n";
  return out.str();
}

}  // namespace pb4u

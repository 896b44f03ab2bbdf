// Evaluation, export and simulation on the tiny dataset with a model trained for a few
// steps: export -> load gives identical predictions, evaluate reports every active term
// and survives a diverging model, simulate writes every frame in every format, a body-less
// scene has no collision or friction, and corrupt or mismatched model files fail cleanly.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include "pb4u/data/dataset.h"
#include "pb4u/eval/evaluate.h"
#include "pb4u/eval/frames_csv.h"
#include "pb4u/model/model_file.h"
#include "pb4u/rollout/rollout.h"
#include "pb4u/io/module_hdf5.h"
#include "pb4u/mesh/topology.h"
#include "pb4u/physics/body_queries.h"
#include "pb4u/io/point_cache.h"
#include "pb4u/sim/simulate.h"
#include "pb4u/train/trainer.h"
#include "pb4u/train/training_data.h"
#include "pb4u/util/error.h"
#include "pb4u/util/median.h"
#include "pb4u/util/runtime.h"
#include "eval/eval_test_util.h"
#include "test_util.h"

namespace pb4u {
namespace {
namespace fs = std::filesystem;
using test::tiny_eval;

using test::kSource;

// A model trained for a few steps (its weights are what matters here, not its quality).
const std::string& tiny_checkpoint() {
  static const std::string path = [] {
    configure_threads(1);
    const std::string out = test::temp_dir("eval_tinyrun");
    TrainConfig c = load_config<TrainConfig>(kSource + "/configs/train/tiny.yaml",
                                             {"data.dataset=" + test::tiny_dataset(), "run.out=" + out,
                                              "run.steps=12", "run.checkpoint_every=12"});
    Trainer trainer(c, config_to_yaml(c), load_training_data(c.data), false);
    trainer.run();
    return out + "/final.pt";
  }();
  return path;
}

// The same model with a NaN in its decoder: every step is non-finite.
ModelFile poisoned(const ModelFile& m) {
  ModelFile bad = load_model_file(m.path);
  torch::NoGradGuard guard;
  for (auto& p : bad.model->decoder->named_parameters())
    if (p.key().find("bias") != std::string::npos) p.value().fill_(std::numeric_limits<float>::quiet_NaN());
  return bad;
}

TEST(ModelFile, ExportLoadsWithIdenticalPredictions) {
  ModelFile ckpt = load_model_file(tiny_checkpoint());
  EXPECT_EQ(ckpt.source, "training checkpoint");
  const std::string out = test::temp_dir("export") + "/model.h5";
  export_model_file(ckpt, out);
  ModelFile exported = load_model_file(out);
  EXPECT_EQ(exported.source, "export");
  EXPECT_EQ(exported.step, ckpt.step);
  EXPECT_EQ(exported.config_yaml, ckpt.config_yaml);
  EXPECT_DOUBLE_EQ(exported.model->mean_edge_length_base(), ckpt.model->mean_edge_length_base());
  EXPECT_DOUBLE_EQ(exported.model->propagation_distance(), ckpt.model->propagation_distance());

  // The portable attributes a reader without pb4u sees.
  auto attrs = read_hdf5_attributes(out);
  EXPECT_EQ(attrs.at("format"), kExportFormat);
  EXPECT_EQ(attrs.at("format_version"), std::to_string(kExportFormatVersion));
  EXPECT_DOUBLE_EQ(std::stod(attrs.at("lbar_base")), ckpt.model->mean_edge_length_base());
  EXPECT_EQ(std::stoll(attrs.at("parameter_count")), parameter_count(*ckpt.model));
  auto inspect = test::run_pb4u("-q inspect " + out);
  ASSERT_EQ(inspect.exit_code, 0) << inspect.err;
  for (const std::string& key : std::vector<std::string>{"method: Pb4U", "parameters: " + attrs.at("parameter_count"), "calibration: Lbar_base",
                                "k_base: " + std::to_string(ckpt.config.k_base)})
    EXPECT_NE(inspect.out.find(key), std::string::npos) << key << "\n" << inspect.out;

  // One rollout step on a tiny-dataset garment, bit for bit.
  Dataset data = read_dataset(test::tiny_dataset());
  const Garment& g = data.bodies[0].garments[0].levels[0];
  GarmentTopology topology = build_garment_topology(g.mesh);
  FrameState state;
  state.x = matrix_to_tensor(g.mesh.V);
  state.x_prev = state.x - 0.001;
  state.effects = Effects::from_names({"gravity"}, "test");
  torch::Tensor a = ckpt.model->step(state, topology), b = exported.model->step(state, topology);
  EXPECT_TRUE(torch::equal(a, b));
  EXPECT_GT((a - state.x).abs().max().item<double>(), 0.0);  // the step did move the cloth
}

TEST(ModelFile, ExportSetChangesOnlyInferenceSwitches) {
  const std::string dir = test::temp_dir("export_set");
  auto r = test::run_pb4u("-q export --checkpoint " + tiny_checkpoint() + " --out " + dir +
                          "/detail.h5 --set update_scaling=detail --set model.smooth_distance=0.08 --set contact_projection=0.002 "
                          "--set strain_limit=0.1 --set refine_iterations=3");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ModelFile ckpt = load_model_file(tiny_checkpoint()), detail = load_model_file(dir + "/detail.h5");
  EXPECT_EQ(detail.config.refine_iterations, 3);
  EXPECT_EQ(ckpt.config.refine_iterations, 0);
  EXPECT_EQ(ckpt.config.update_scaling, "on");
  EXPECT_EQ(detail.config.update_scaling, "detail");
  EXPECT_DOUBLE_EQ(detail.config.smooth_distance, 0.08);
  EXPECT_DOUBLE_EQ(detail.config.contact_projection, 0.002);
  EXPECT_EQ(ckpt.config.contact_projection, 0.0);
  EXPECT_DOUBLE_EQ(detail.config.strain_limit, 0.1);
  EXPECT_EQ(ckpt.config.strain_limit, 0.0);
  EXPECT_EQ(method_name(detail.config), "Pb4U + projection + strain limit + 3 it");
  EXPECT_EQ(detail.model->config.update_scaling, "detail");  // the network computes with it
  auto pa = ckpt.model->named_parameters(), pb = detail.model->named_parameters();
  for (const auto& p : pa) EXPECT_TRUE(torch::equal(p.value(), pb[p.key()])) << p.key();
  // Anything that would need other weights, or a bad value, is refused naming the key; no file.
  for (const std::string& bad :
       {std::string("latent=32"), std::string("update_scaling=half"), std::string("refine_contact=soft")}) {
    auto e = test::run_pb4u("export --checkpoint " + tiny_checkpoint() + " --out " + dir + "/bad.h5 --set " + bad);
    EXPECT_EQ(e.exit_code, 1) << bad;
    EXPECT_NE(e.err.find(bad.substr(0, bad.find('='))), std::string::npos) << e.err;
    EXPECT_FALSE(fs::exists(dir + "/bad.h5"));
  }
}

TEST(ModelFile, CorruptOrMismatchedFilesFailNamingTheFile) {
  const ModelFile ckpt = load_model_file(tiny_checkpoint());
  const std::string dir = test::temp_dir("badmodel");
  const std::string good = dir + "/good.h5";
  export_model_file(ckpt, good);

  // Truncated export.
  std::string bytes = test::read_file(good);
  test::write_file(dir + "/truncated.h5", bytes.substr(0, bytes.size() / 2));
  // A model of another width: same format, shapes disagree with the stored config.
  ModelConfig wide = ckpt.config;
  wide.latent = ckpt.config.latent * 2;
  ModelFile other{Pb4uNet(wide), wide, config_to_yaml(wide), "x", "export", 0};
  other.model->calibrate(0.05);
  export_model_file(other, dir + "/wide.h5");
  {
    // Swap in the narrow config: the datasets no longer fit it.
    std::map<std::string, std::string> attrs = read_hdf5_attributes(dir + "/wide.h5");
    attrs["model_config"] = ckpt.config_yaml;
    save_module_hdf5(dir + "/mismatched.h5", *other.model, attrs);
    attrs = read_hdf5_attributes(good);
    attrs["format_version"] = "99";
    save_module_hdf5(dir + "/future.h5", *ckpt.model, attrs);
  }
  test::write_file(dir + "/garbage.pt", "not a checkpoint at all");

  for (const char* name : {"truncated.h5", "mismatched.h5", "future.h5", "garbage.pt", "missing.pt"}) {
    const std::string path = dir + "/" + name;
    try {
      load_model_file(path);
      ADD_FAILURE() << name << " loaded";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
    auto r = test::run_pb4u("-q export --checkpoint " + path + " --out " + dir + "/out.h5");
    EXPECT_NE(r.exit_code, 0) << name;
    EXPECT_NE(r.err.find(name), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir + "/out.h5"));
  }
}

TEST(MethodName, FollowsTheModelConfig) {
  ModelConfig c;
  EXPECT_EQ(method_name(c), "Pb4U");
  c.update_scaling = "off";
  EXPECT_EQ(method_name(c), "Pb4U w/o US");
  c.propagation_control = "off";
  EXPECT_EQ(method_name(c), "Pb4U w/o both");
  c.update_scaling = "on";
  EXPECT_EQ(method_name(c), "Pb4U w/o PC");
  c.kind = "mgn";
  EXPECT_EQ(method_name(c), "MGN w/ US");
  c.update_scaling = "off";
  EXPECT_EQ(method_name(c), "MGN");  // the paper's baseline: fixed depth, no scaling
  c.contact_projection = 0.002;
  EXPECT_EQ(method_name(c), "MGN + projection");
  c.strain_limit = 0.1;
  EXPECT_EQ(method_name(c), "MGN + projection + strain limit");
  c.kind = "hood";
  EXPECT_EQ(method_name(c), "HOOD + projection + strain limit");
  c.contact_projection = c.strain_limit = 0;
  EXPECT_EQ(method_name(c), "HOOD");
}

TEST(Evaluate, JsonHasEveryActiveTermPerLevelAndMethod) {
  const std::string ckpt = tiny_checkpoint();
  const std::string exported = test::temp_dir("eval_json") + "/m.h5";
  ASSERT_EQ(test::run_pb4u("-q export --checkpoint " + ckpt + " --out " + exported).exit_code, 0);
  auto r = test::run_pb4u("-q evaluate --checkpoint " + ckpt + " --checkpoint " + exported + " --config " + kSource +
                          "/configs/eval/tiny.yaml --set dataset=" + test::tiny_dataset() + " --format json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json report = nlohmann::json::parse(r.out);  // valid JSON: no nan either
  std::set<int> level_numbers;
  int undiverged = 0;
  for (const auto& level : report.at("levels")) {
    level_numbers.insert(level.at("level").get<int>());
    const auto& methods = level.at("methods");
    // Two methods named from their configs, disambiguated by file stem.
    EXPECT_TRUE(methods.contains("Pb4U (final)")) << methods.dump();
    EXPECT_TRUE(methods.contains("Pb4U (m)")) << methods.dump();
    for (const auto& [name, method] : methods.items()) {
      // Every active term and the total, with a value (not null), per method and per rollout.
      std::vector<nlohmann::json> holders{method};
      for (const auto& sequence : method.at("sequences")) holders.push_back(sequence);
      for (const auto& holder : holders)
        for (const char* key : {"stretch", "bending", "collision", "inertia", "gravity", "friction", "total"})
          EXPECT_TRUE(holder.contains(key) && holder.at(key).is_number())
              << name << " " << key << ": " << holder;
      if (method.at("diverged") == false && method.at("diverged_at_frame").is_null()) ++undiverged;
    }
  }
  EXPECT_TRUE(level_numbers.count(1) && level_numbers.count(3)) << r.out;
  EXPECT_GT(undiverged, 0) << r.out;

  // The table: one row per term and the total; the export equals the checkpoint in every cell.
  r = test::run_pb4u("-q evaluate --checkpoint " + ckpt + " --checkpoint " + exported + " --config " + kSource +
                     "/configs/eval/tiny.yaml --set dataset=" + test::tiny_dataset() + " --set levels=[1]");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream lines(r.out);
  int rows = 0;
  for (std::string line; std::getline(lines, line);) {
    std::istringstream cells(line);
    std::string label, a, b;
    cells >> label >> a >> b;
    for (const char* term : {"Stretch", "Bending", "Collision", "Inertia", "Gravity", "Friction", "Total"})
      if (label == term) {
        ++rows;
        EXPECT_EQ(a, b) << line;
        EXPECT_NE(a.find("E"), std::string::npos) << line;  // 5.30E-02 style
      }
  }
  EXPECT_EQ(rows, 7) << r.out;
}

// --frames-dir: one CSV per rollout whose frames average to the sequence's summary.
TEST(Evaluate, FramesDirHoldsEveryFrameOfEveryRollout) {
  EXPECT_EQ(file_name_from("Pb4U + 10 it + to 1 mm (barrier)"), "Pb4U_10_it_to_1_mm_barrier");
  EXPECT_EQ(file_name_from("tshirt_cmu_131_02_cmu131"), "tshirt_cmu_131_02_cmu131");
  const std::string dir = test::temp_dir("eval_frames");
  auto r = test::run_pb4u("-q evaluate --checkpoint " + tiny_checkpoint() + " --config " + kSource +
                          "/configs/eval/tiny.yaml --set dataset=" + test::tiny_dataset() +
                          " --set levels=[1] --format json --frames-dir " + dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto methods = nlohmann::json::parse(r.out).at("levels")[0].at("methods");
  ASSERT_EQ(methods.size(), 1u);
  const std::string method = methods.begin().key();
  int files = 0;
  std::vector<double> all_residuals;  // every sequence's frames: the method's median
  for (const auto& q : methods.begin().value().at("sequences")) {
    const std::string path = dir + "/lv1/" + file_name_from(method) + "/" +
                             file_name_from(q.at("garment").get<std::string>() + "_" + q.at("motion").get<std::string>() +
                                            "_" + q.at("body").get<std::string>()) + ".csv";
    ASSERT_TRUE(fs::exists(path)) << path;
    ++files;
    const auto rows = read_csv(path);
    ASSERT_EQ(int(rows.size()) - 1, q.at("frames").get<int>()) << path;
    const auto& head = rows[0];
    auto column = [&](const std::string& name) {
      const size_t c = std::find(head.begin(), head.end(), name) - head.begin();
      EXPECT_LT(c, head.size()) << name;
      return c;
    };
    const size_t positive = column("positive"), stretch = column("stretch"), inside = column("penetrating_fraction"),
                 residual = column("residual_mm");
    double sum_positive = 0, sum_stretch = 0, largest = 0;
    std::vector<double> residuals;
    for (size_t f = 1; f < rows.size(); ++f) {
      EXPECT_EQ(rows[f][0], std::to_string(f));
      residuals.push_back(std::stod(rows[f][residual]));
      sum_positive += std::stod(rows[f][positive]);
      sum_stretch += std::stod(rows[f][stretch]);
      largest = std::max(largest, std::stod(rows[f][positive]));
      EXPECT_GE(std::stod(rows[f][inside]), 0.0);
    }
    const double n = double(rows.size() - 1);
    const double mean = q.at("positive_energy").get<double>();
    // The JSON prints 9 significant digits; the CSV every digit.
    EXPECT_NEAR(sum_positive / n, mean, 1e-8 * std::abs(mean) + 1e-15) << path;
    EXPECT_NEAR(sum_stretch / n, q.at("stretch").get<double>(), 1e-8 * std::abs(mean) + 1e-15) << path;
    EXPECT_NEAR(largest, q.at("max_positive_energy").get<double>(), 1e-8 * largest) << path;
    // The residual's median over the frames (the mean is a row like the terms).
    const double median_residual = median(residuals);
    EXPECT_NEAR(median_residual, q.at("median_residual_mm").get<double>(), 1e-8 * median_residual) << path;
    all_residuals.insert(all_residuals.end(), residuals.begin(), residuals.end());
    // The network's own step: no solve, no contact account.
    EXPECT_EQ(std::find(head.begin(), head.end(), "contact_excluded"), head.end());
  }
  EXPECT_GT(files, 0);
  const double median_residual = median(all_residuals);
  EXPECT_NEAR(median_residual, methods.begin().value().at("median_residual_mm").get<double>(), 1e-8 * median_residual);
  // Refined with barrier contact (the solver's default), each frame also has the solve's account.
  r = test::run_pb4u("-q evaluate --checkpoint " + tiny_checkpoint() + " --config " + kSource +
                     "/configs/eval/tiny.yaml --set dataset=" + test::tiny_dataset() +
                     " --set levels=[1] --set max_sequences=1 --set max_frames=3 --refine 2 --format json --frames-dir " +
                     dir + "/refined");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto refined = nlohmann::json::parse(r.out).at("levels")[0].at("methods");
  const auto& q = refined.begin().value().at("sequences")[0];
  const auto rows = read_csv(dir + "/refined/lv1/" + file_name_from(refined.begin().key()) + "/" +
                             file_name_from(q.at("garment").get<std::string>() + "_" +
                                            q.at("motion").get<std::string>() + "_" + q.at("body").get<std::string>()) +
                             ".csv");
  ASSERT_EQ(rows.size(), 4u);
  for (const char* name : {"contact_excluded", "caught_by_body", "body_lag_mm"}) {
    const size_t c = std::find(rows[0].begin(), rows[0].end(), name) - rows[0].begin();
    ASSERT_LT(c, rows[0].size()) << name;
    for (size_t f = 1; f < rows.size(); ++f) EXPECT_GE(std::stod(rows[f][c]), 0.0) << name;
  }
}

// --minimum-every N: every N-th frame of every rollout solved on to its minimum, its distance
// and energy gap in the frames CSV, and their median and largest in the JSON and the table.
TEST(Evaluate, MinimumEverySamplesFramesIntoTheFramesCsvTheJsonAndTheTable) {
  const std::string dir = test::temp_dir("eval_minimum");
  const std::string args = "-q evaluate --checkpoint " + tiny_checkpoint() + " --config " + kSource +
                           "/configs/eval/tiny.yaml --set dataset=" + test::tiny_dataset() +
                           " --set levels=[1] --set max_sequences=1 --set max_frames=4 ";
  auto r = test::run_pb4u(args + "--minimum-every 2 --format json --frames-dir " + dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto methods = nlohmann::json::parse(r.out).at("levels")[0].at("methods");
  ASSERT_EQ(methods.size(), 1u);
  const auto& method = methods.begin().value();
  std::vector<double> distances;
  for (const auto& q : method.at("sequences")) {
    const auto rows = read_csv(dir + "/lv1/" + file_name_from(methods.begin().key()) + "/" +
                               file_name_from(q.at("garment").get<std::string>() + "_" +
                                              q.at("motion").get<std::string>() + "_" +
                                              q.at("body").get<std::string>()) +
                               ".csv");
    ASSERT_EQ(rows.size(), 5u);  // the header and frames 1-4
    const size_t d = std::find(rows[0].begin(), rows[0].end(), "distance_to_minimum_mm") - rows[0].begin();
    const size_t g = std::find(rows[0].begin(), rows[0].end(), "energy_gap_j") - rows[0].begin();
    ASSERT_LT(d, rows[0].size());
    ASSERT_LT(g, rows[0].size());
    std::vector<double> sampled;
    for (size_t f = 1; f <= 4; ++f) {
      const double distance = std::stod(rows[f][d]), gap = std::stod(rows[f][g]);
      if (f % 2 == 1) {
        EXPECT_TRUE(std::isnan(distance) && std::isnan(gap)) << f;
        continue;
      }
      EXPECT_GT(distance, 0.1) << f;  // mm: the untrained network's step is not at its minimum
      EXPECT_GT(gap, 0.0) << f;       // J: lower there
      sampled.push_back(distance);
    }
    const auto& m = q.at("distance_to_minimum");
    EXPECT_EQ(m.at("frames").get<int>(), 2);
    EXPECT_NEAR(m.at("median_mm").get<double>(), median(sampled), 1e-7 * median(sampled));
    EXPECT_NEAR(m.at("max_mm").get<double>(), std::max(sampled[0], sampled[1]), 1e-7 * sampled[1]);
    distances.insert(distances.end(), sampled.begin(), sampled.end());
  }
  EXPECT_EQ(method.at("distance_to_minimum").at("frames").get<size_t>(), distances.size());
  EXPECT_NEAR(method.at("distance_to_minimum").at("median_mm").get<double>(), median(distances),
              1e-7 * median(distances));
  r = test::run_pb4u(args + "--minimum-every 4");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("To min. mm"), std::string::npos) << r.out;
  // Off (the default): neither the key nor the rows.
  r = test::run_pb4u(args + "--format json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find("distance_to_minimum"), std::string::npos);
}

TEST(Evaluate, WithoutGravityTheTermIsAbsent) {
  const ModelFile m = load_model_file(tiny_checkpoint());
  auto levels = evaluate(tiny_eval({"effects=[collision, friction]", "levels=[1]", "max_frames=2"}), {{"Pb4U", &m}});
  ASSERT_EQ(levels.size(), 1u);
  ASSERT_TRUE(levels[0].methods[0].mean);
  EXPECT_FALSE(levels[0].methods[0].mean->has("gravity"));
  EXPECT_TRUE(levels[0].methods[0].mean->has("collision"));
  const nlohmann::json report = nlohmann::json::parse(format_json(levels));
  const nlohmann::json& method = report.at("levels")[0].at("methods").at("Pb4U");
  EXPECT_TRUE(method.contains("collision")) << method;
  EXPECT_FALSE(method.contains("gravity")) << method;
  // One step's median wall time, beside the figures.
  EXPECT_GT(method.at("step_ms").get<double>(), 0.0) << method;
  EXPECT_NE(format_table(levels).find("Step ms"), std::string::npos);
  EXPECT_NE(format_csv(levels).find(",step_ms,"), std::string::npos);
  for (const auto& sequence : method.at("sequences")) EXPECT_FALSE(sequence.contains("gravity")) << sequence;
}

TEST(Evaluate, ASettledStartIsFreeOfTheBodyAndEveryMethodRollsOutFromIt) {
  const ModelFile m = load_model_file(tiny_checkpoint());
  // The tiny dataset's test motion is the fast spin; with the default carry its body's moves
  // stall where it turns under the sleeves (docs/robustness.md), so the solver rides.
  const std::vector<std::string> sets{"levels=[1]", "max_sequences=1", "max_frames=2", "garments=[tshirt]",
                                      "physics.solver.body_carry=ride"};
  std::vector<std::string> settled_sets = sets;
  settled_sets.push_back("start=settled");
  settled_sets.push_back("settle_steps=4");
  const EvalMethod network{"Pb4U", &m, ""}, reference{"Reference", nullptr, ""};
  const auto settled = evaluate(tiny_eval(settled_sets), {network, reference});
  const auto skinned = evaluate(tiny_eval(sets), {network, reference});
  ASSERT_EQ(settled[0].methods.size(), 2u);
  // Skinned, the t-shirt's coarse edges cut the spinning arms from the start, and no push frees
  // them. Carried by the solver from the bind pose, the cloth never enters the body: no vertex
  // inside and no cloth edge through it on any frame.
  const MethodResult& solver = settled[0].methods[1];
  ASSERT_TRUE(solver.penetration && skinned[0].methods[1].penetration);
  EXPECT_GT(skinned[0].methods[1].penetration->max_edges_through, 0);
  EXPECT_EQ(solver.penetration->max_penetrating_fraction, 0.0);
  EXPECT_EQ(solver.penetration->max_edges_through, 0);
  EXPECT_FALSE(solver.diverged);
  // The network starts there too, not at the skinned frame: its first frames differ.
  const MethodResult& from_settled = settled[0].methods[0];
  const MethodResult& from_skinned = skinned[0].methods[0];
  ASSERT_TRUE(from_settled.mean && from_skinned.mean);
  EXPECT_NE(from_settled.per_sequence[0].positive_energy, from_skinned.per_sequence[0].positive_energy);
  // Without a body there is no pose to settle into: the key is named.
  try {
    evaluate(tiny_eval({"effects=[gravity, pins]", "pins.top_band=0.02", "max_frames=2", "levels=[1]",
                        "start=settled"}),
             {network});
    FAIL() << "start: settled without a body was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("start: settled"), std::string::npos) << e.what();
  }
}

TEST(Evaluate, ADivergingModelIsReportedNotCrashed) {
  const ModelFile good = load_model_file(tiny_checkpoint());
  const ModelFile bad = poisoned(good);
  auto levels = evaluate(tiny_eval({"levels=[1]"}), {{"Pb4U", &good}, {"Broken", &bad}});
  const MethodResult& ok = levels[0].methods[0];
  const MethodResult& broken = levels[0].methods[1];
  EXPECT_FALSE(ok.diverged);
  EXPECT_TRUE(broken.diverged);
  EXPECT_EQ(broken.diverged_at_frame, 1);
  EXPECT_FALSE(broken.mean);
  EXPECT_EQ(broken.frames, 0);
  const std::string json = format_json(levels), table = format_table(levels);
  const nlohmann::json methods = nlohmann::json::parse(json).at("levels")[0].at("methods");  // no nan
  EXPECT_EQ(methods.at("Broken").at("diverged"), true) << json;
  EXPECT_EQ(methods.at("Broken").at("diverged_at_frame"), 1) << json;
  EXPECT_EQ(methods.at("Pb4U").at("diverged"), false) << json;
  EXPECT_EQ(table.find("nan"), std::string::npos) << table;
  EXPECT_NE(table.find("Broken: diverged at frame 1"), std::string::npos) << table;
}

SceneConfig hanging_scene(int frames) {
  return load_config<SceneConfig>(kSource + "/configs/scenes/hanging_cloth.yaml",
                                  {"frames=" + std::to_string(frames), "garment.resolution=8"});
}

TEST(Simulate, WritesEveryFrameInEveryFormat) {
  const ModelFile m = load_model_file(tiny_checkpoint());
  for (const char* format : {"obj", "ply"}) {
    const std::string out = test::temp_dir(std::string("sim_") + format);
    SceneConfig scene = hanging_scene(5);
    scene.outputs.mesh_format = format;
    scene.outputs.plot = false;
    SimulateResult r = simulate(scene, "hanging_cloth.yaml", &m, out);
    EXPECT_FALSE(r.diverged);
    EXPECT_EQ(r.frames, 6);  // the start frame and 5 steps
    for (int f = 0; f < 6; ++f) EXPECT_TRUE(fs::exists(frame_file(out, "garment", f, format))) << f;
    EXPECT_FALSE(fs::exists(frame_file(out, "garment", 6, format)));
    EXPECT_FALSE(fs::exists(frame_file(out, "body", 0, format)));  // no body in the scene
    auto cache = read_pc2(out + "/garment.pc2");
    ASSERT_EQ(cache.size(), 6u);
    EXPECT_EQ(cache[0].rows(), 64);
    EXPECT_TRUE(fs::exists(out + "/rollout.h5"));
    std::ifstream csv(out + "/energies.csv");
    std::string header;
    std::getline(csv, header);
    int lines = 0;
    for (std::string l; std::getline(csv, l);) ++lines;
    EXPECT_EQ(lines, 6);
    // A scene without a body has no collision or friction column.
    EXPECT_EQ(header, "frame,stretch,bending,inertia,gravity,total,residual_mm");
  }
}

TEST(Simulate, BodylessSceneBuildsNoBodyQueriesAndPinsHold) {
  const ModelFile m = load_model_file(tiny_checkpoint());
  const int64_t trees = body_kd_trees_built();
  SceneConfig scene = hanging_scene(4);
  SceneSetup setup = build_scene(scene, "hanging_cloth.yaml");
  ASSERT_EQ(setup.pinned.size(), 8u);  // the top row of an 8 x 8 cloth
  RolloutInput in;
  in.garment_rest = setup.garment;
  in.x0 = in.x_prev = setup.x0;
  in.pinned = setup.pinned;
  in.effects = setup.effects;
  in.steps = 4;
  GarmentTopology topology = build_garment_topology(setup.garment);
  Eigen::MatrixXd last;
  RolloutResult r = run_rollout(in, network_stepper(m, topology), scene.physics,
                                [&](int, const Eigen::MatrixXd& x, const EnergyReport& report,
                                    const PenetrationFigures* penetration) {
                                  EXPECT_EQ(penetration, nullptr);  // no body, nothing to measure
                                  last = x;
                                  EXPECT_FALSE(report.has("collision"));
                                  EXPECT_FALSE(report.has("friction"));
                                });
  EXPECT_EQ(body_kd_trees_built(), trees);
  ASSERT_EQ(r.reports.size(), 4u);
  for (int i : setup.pinned) EXPECT_EQ((last.row(i) - setup.x0.row(i)).norm(), 0.0) << i;
  EXPECT_GT((last - setup.x0).norm(), 0.0);
}

TEST(Simulate, DivergenceStopsKeepsFramesAndFailsTheCommand) {
  const ModelFile bad = poisoned(load_model_file(tiny_checkpoint()));
  const std::string dir = test::temp_dir("sim_diverge");
  export_model_file(bad, dir + "/bad.h5");
  auto r = test::run_pb4u("-q simulate --checkpoint " + dir + "/bad.h5 --scene " + kSource +
                          "/configs/scenes/hanging_cloth.yaml --frames 5 --out " + dir + "/out");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("diverged at frame 1"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("vertex"), std::string::npos) << r.err;
  EXPECT_EQ(read_pc2(dir + "/out/garment.pc2").size(), 1u);  // the start frame, kept
}

TEST(Simulate, ReferenceMethodNeedsNoCheckpointAndHoldsPins) {
  const std::string out = test::temp_dir("sim_reference");
  auto r = test::run_pb4u("-q simulate --method reference --scene " + kSource +
                          "/configs/scenes/hanging_cloth.yaml --set garment.resolution=6 --frames 3 --format none --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto frames = read_pc2(out + "/garment.pc2");
  ASSERT_EQ(frames.size(), 4u);
  // The top row (6 vertices) is pinned; the rest falls.
  EXPECT_EQ((frames[3].topRows(6) - frames[0].topRows(6)).norm(), 0.0);
  EXPECT_LT(frames[3].col(1).tail(30).sum(), frames[0].col(1).tail(30).sum());
  r = test::run_pb4u("-q simulate --scene " + kSource + "/configs/scenes/hanging_cloth.yaml --out " + out);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--checkpoint"), std::string::npos) << r.err;
}

TEST(Simulate, MinimumEverySolvesTheSampledFramesOnToTheirMinimum) {
  // Every 2nd frame the solver goes on from the step to its minimum: the untrained network's
  // step is millimetres from it and higher in energy; the reference's own step is at it.
  const std::string out = test::temp_dir("sim_minimum");
  const std::string scene = kSource + "/configs/scenes/hanging_cloth.yaml --set garment.resolution=6 --frames 4 "
                                      "--format none --preview off --minimum-every ";
  auto column = [](const std::vector<std::vector<std::string>>& csv, const std::string& name) {
    const size_t c = std::find(csv[0].begin(), csv[0].end(), name) - csv[0].begin();
    EXPECT_LT(c, csv[0].size()) << name;
    std::vector<double> v;
    for (size_t f = 1; f < csv.size() && c < csv[0].size(); ++f) v.push_back(std::stod(csv[f][c]));
    return v;  // frames 0..
  };
  auto r = test::run_pb4u("simulate --checkpoint " + tiny_checkpoint() + " --scene " + scene + "2 --out " + out + "/net");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("distance to the minimum on 2 sampled frames"), std::string::npos) << r.err;
  auto csv = read_csv(out + "/net/energies.csv");
  std::vector<double> distance = column(csv, "distance_to_minimum_mm"), gap = column(csv, "energy_gap_j");
  ASSERT_EQ(distance.size(), 5u);
  for (int f : {0, 1, 3}) EXPECT_TRUE(std::isnan(distance[size_t(f)]) && std::isnan(gap[size_t(f)])) << f;
  for (int f : {2, 4}) {
    EXPECT_GT(distance[size_t(f)], 0.1) << f;  // mm
    EXPECT_GT(gap[size_t(f)], 0.0) << f;       // J: lower at the minimum
  }
  r = test::run_pb4u("-q simulate --method reference --scene " + scene + "1 --out " + out + "/reference");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  csv = read_csv(out + "/reference/energies.csv");
  distance = column(csv, "distance_to_minimum_mm");
  gap = column(csv, "energy_gap_j");
  for (size_t f = 1; f < distance.size(); ++f) {
    EXPECT_LT(distance[f], 0.01) << f;   // mm: the solver stopped within 0.001 mm steps of it
    EXPECT_LT(std::abs(gap[f]), 1e-6) << f;  // J
  }
}

TEST(Simulate, RefineRunsTheSolverFromTheNetworksStepAndNeedsTheNetwork) {
  const std::string out = test::temp_dir("sim_refine");
  const std::string scene = kSource + "/configs/scenes/hanging_cloth.yaml --set garment.resolution=6 --frames 3 "
                                      "--format none --preview off";
  auto r = test::run_pb4u("simulate --checkpoint " + tiny_checkpoint() + " --scene " + scene + " --refine 0 --out " +
                          out + "/net");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("(network step)"), std::string::npos) << r.err;  // 0: off
  r = test::run_pb4u("simulate --checkpoint " + tiny_checkpoint() + " --scene " + scene + " --refine 20 --out " +
                     out + "/refined");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("(network step + refinement)"), std::string::npos) << r.err;
  // The solver moves the untrained network's steps towards the energy's minimum.
  const auto net = read_csv(out + "/net/energies.csv"), refined = read_csv(out + "/refined/energies.csv");
  ASSERT_EQ(net.size(), refined.size());
  const size_t residual = std::find(net[0].begin(), net[0].end(), "residual_mm") - net[0].begin();
  ASSERT_LT(residual, net[0].size());
  EXPECT_LT(std::stod(refined[2][residual]), 0.1 * std::stod(net[2][residual]));
  // The summary line's residual median is energies.csv's, to the 3 digits it prints.
  std::vector<double> refined_residuals;
  for (size_t f = 2; f < refined.size(); ++f) refined_residuals.push_back(std::stod(refined[f][residual]));
  const size_t at = r.err.find("residual median ");
  ASSERT_NE(at, std::string::npos) << r.err;
  EXPECT_NEAR(std::stod(r.err.substr(at + 16)), median(refined_residuals), 5e-3 * median(refined_residuals)) << r.err;
  // The same refinement as a switch of the model file.
  ASSERT_EQ(test::run_pb4u("-q export --checkpoint " + tiny_checkpoint() + " --set refine_iterations=20 --out " +
                           out + "/refined.h5")
                .exit_code,
            0);
  r = test::run_pb4u("simulate --checkpoint " + out + "/refined.h5 --scene " + scene + " --out " + out + "/file");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto from_file = read_csv(out + "/file/energies.csv");
  EXPECT_NEAR(std::stod(from_file[2][residual]), std::stod(refined[2][residual]),
              1e-9 + 1e-6 * std::stod(refined[2][residual]));
  // The refinement's settings as switches of the file give the frames the scene's keys give:
  // exported with `switches`, simulated against the tiny checkpoint with `scene_flags`.
  // `both`: scene keys given to both runs.
  auto file_matches_scene = [&](const std::string& name, const std::string& switches, const std::string& scene_flags,
                                const std::string& method, const std::string& both = "") {
    const std::string file = out + "/" + name + ".h5";
    EXPECT_EQ(test::run_pb4u("-q export --checkpoint " + tiny_checkpoint() + " " + switches + " --out " + file).exit_code, 0);
    EXPECT_EQ(method_name(load_model_file(file).config), method);
    auto run = test::run_pb4u("-q simulate --checkpoint " + file + " --scene " + scene + " " + both + " --out " + out +
                              "/" + name + "_file");
    EXPECT_EQ(run.exit_code, 0) << run.err;
    run = test::run_pb4u("-q simulate --checkpoint " + tiny_checkpoint() + " --scene " + scene + " " + scene_flags +
                         " " + both + " --out " + out + "/" + name + "_scene");
    EXPECT_EQ(run.exit_code, 0) << run.err;
    const auto from_file = read_csv(out + "/" + name + "_file/energies.csv");
    const auto from_scene = read_csv(out + "/" + name + "_scene/energies.csv");
    EXPECT_EQ(from_file.size(), from_scene.size());
    for (size_t f = 1; f < std::min(from_file.size(), from_scene.size()); ++f)
      EXPECT_EQ(from_file[f], from_scene[f]) << name << ", frame " << f - 1;
    return from_file;
  };
  // Barrier contact (no body here) and the strain barrier.
  const auto limited_file = file_matches_scene(
      "limited", "--set refine_iterations=20 --set refine_contact=barrier --set refine_strain_limit=0.05",
      "--refine 20 --set physics.solver.contact=barrier --set physics.solver.strain_limit=0.05",
      "Pb4U + 20 it (barrier, strain barrier)");
  // The limit moved the refined cloth: the untrained network stretches the hanging cloth past 5%.
  ASSERT_GT(limited_file.size(), 3u);
  EXPECT_NE(limited_file[3], read_csv(out + "/refined/energies.csv")[3]);
  // The scene's other solver keys reach the file's refinement as they reach the scene's: a wider
  // strain barrier band gives both the same frames, and frames other than the default band's.
  const auto wide_band = file_matches_scene(
      "wide_band", "--set refine_iterations=20 --set refine_contact=barrier --set refine_strain_limit=0.05",
      "--refine 20 --set physics.solver.contact=barrier --set physics.solver.strain_limit=0.05",
      "Pb4U + 20 it (barrier, strain barrier)", "--set physics.solver.strain_barrier_gap=0.03");
  ASSERT_EQ(wide_band.size(), limited_file.size());
  EXPECT_NE(wide_band[3], limited_file[3]);
  // Refined to a tolerance.
  const auto tol_file =
      file_matches_scene("tolerance", "--set refine_tolerance_mm=0.5 --set refine_contact=barrier",
                         "--refine-tolerance 0.5 --set physics.solver.contact=barrier", "Pb4U + to 0.5 mm (barrier)");
  // Every refined step ends within its tolerance of the minimum (the solver's own residual).
  for (size_t f = 2; f < tol_file.size(); ++f) EXPECT_LT(std::stod(tol_file[f][residual]), 0.5) << "frame " << f - 1;
  r = test::run_pb4u("-q simulate --method reference --scene " + scene + " --refine 2 --out " + out + "/x");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--refine: refines the network's step"), std::string::npos) << r.err;
}

TEST(Evaluate, RefineNamesTheColumnAndLowersTheResidual) {
  const std::string args = "-q evaluate --checkpoint " + tiny_checkpoint() + " --config " + kSource +
                           "/configs/eval/tiny.yaml --set dataset=" + test::tiny_dataset() +
                           " --set levels=[1] --format json";
  auto plain = test::run_pb4u(args), refined = test::run_pb4u(args + " --refine 20");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  ASSERT_EQ(refined.exit_code, 0) << refined.err;
  const auto p = nlohmann::json::parse(plain.out).at("levels")[0].at("methods");
  const auto r = nlohmann::json::parse(refined.out).at("levels")[0].at("methods");
  ASSERT_EQ(p.size(), 1u);
  ASSERT_EQ(r.size(), 1u);
  const std::string name = p.begin().key();
  ASSERT_TRUE(r.contains(name + " + 20 it")) << r.dump();
  EXPECT_LT(r.at(name + " + 20 it").at("residual_mm").get<double>(), p.at(name).at("residual_mm").get<double>());
}

TEST(Scene, SquareClothAndBadScenes) {
  TriMesh cloth = square_cloth(0.5, 5, 1.0);
  EXPECT_EQ(cloth.V.rows(), 25);
  EXPECT_EQ(cloth.F.rows(), 32);
  EXPECT_DOUBLE_EQ(cloth.V.col(1).maxCoeff(), 1.0);
  EXPECT_NEAR(cloth.V.col(0).maxCoeff() - cloth.V.col(0).minCoeff(), 0.5, 1e-12);
  EXPECT_EQ(boundary_loops(cloth.F).size(), 1u);

  SceneConfig s = hanging_scene(2);
  s.effects = {"gravity", "collision"};
  EXPECT_THROW(build_scene(s, "scene.yaml"), Error);  // collision without a body
  s = hanging_scene(2);
  s.pins.top_band = 0;
  EXPECT_THROW(build_scene(s, "scene.yaml"), Error);  // pins effect, nothing pinned
  const std::string dir = test::temp_dir("badscene");
  test::write_file(dir + "/s.yaml", "frames: 3\ngarmnet: {source: square}\n");
  auto r = test::run_pb4u("-q simulate --method reference --scene " + dir + "/s.yaml --out " + dir + "/o");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("garmnet"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace pb4u

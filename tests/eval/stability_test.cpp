// The held-out stability figures (issue 14) through evaluate and simulate, on the tiny dataset
// with the shipped model and the reference solver: penetration keys, rows and columns with a
// body and none without; one result per sequence; the motion split; body-less evaluation
// pinned by rule; simulate's energy guard from the command line.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "pb4u/data/dataset.h"
#include "pb4u/eval/evaluate.h"
#include "pb4u/io/point_cache.h"
#include "pb4u/sim/simulate.h"
#include "pb4u/util/error.h"
#include "pb4u/util/runtime.h"
#include "eval/eval_test_util.h"
#include "test_util.h"

namespace pb4u {
namespace {
using test::tiny_eval;

using test::kSource;

const ModelFile& shipped() {
  static const ModelFile m = [] {
    configure_threads(1);
    return load_model_file(kSource + "/data/pretrained/pb4u.h5");
  }();
  return m;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Stability, PenaltyColumnIsTheSolverWithPenaltyContact) {
  // `evaluate --method penalty`: the solver with SPEC 3.3's penalty alone, whatever the config's
  // contact (the reference's default: barrier): the same figures as the reference column of a
  // config set to penalty, and not the barrier reference's.
  const EvalConfig config = tiny_eval({"levels=[1]", "max_frames=3", "max_sequences=1"});
  const EvalConfig penalty_config = tiny_eval({"levels=[1]", "max_frames=3", "max_sequences=1",
                                               "physics.solver.contact=penalty"});
  ASSERT_EQ(config.physics.solver.contact, "barrier");
  auto both = evaluate(config, {{"Reference", nullptr}, {"Penalty solver", nullptr, "penalty"}});
  auto by_config = evaluate(penalty_config, {{"Reference", nullptr}});
  const MethodResult &barrier = both[0].methods[0], &penalty = both[0].methods[1], &want = by_config[0].methods[0];
  ASSERT_EQ(penalty.name, "Penalty solver");
  ASSERT_EQ(penalty.per_sequence.size(), want.per_sequence.size());
  for (size_t i = 0; i < want.per_sequence.size(); ++i)
    EXPECT_EQ(penalty.per_sequence[i].positive_energy, want.per_sequence[i].positive_energy) << i;
  EXPECT_NE(barrier.per_sequence[0].positive_energy, penalty.per_sequence[0].positive_energy);
}

TEST(Stability, EvaluateReportsPenetrationAndEverySequence) {
  const EvalConfig config = tiny_eval({"levels=[1]", "max_frames=3", "max_sequences=2"});
  auto levels = evaluate(config, {{"Pb4U", &shipped()}, {"Reference", nullptr}});
  ASSERT_EQ(levels.size(), 1u);
  // One sequence per test motion (at most 2) and garment of each body.
  const Dataset data = read_dataset(config.dataset);
  size_t expected = 0;
  for (const auto& b : data.bodies) {
    int motions = 0;
    for (const auto& m : data.motions) motions += m.body == b.body.name && m.split == "test";
    expected += std::min(motions, 2) * b.garments.size();
  }
  for (const MethodResult& m : levels[0].methods) {
    ASSERT_EQ(m.per_sequence.size(), expected) << m.name;
    ASSERT_TRUE(m.penetration) << m.name;
    double mean_fraction = 0, max_fraction = 0, max_mm = 0;
    for (const SequenceResult& q : m.per_sequence) {
      EXPECT_EQ(q.body, "mannequin");
      EXPECT_NE(q.motion, "rest");
      ASSERT_TRUE(q.penetration) << q.garment << "/" << q.motion;
      EXPECT_GE(q.penetration->penetrating_fraction, 0.0);
      EXPECT_LE(q.penetration->penetrating_fraction, q.penetration->max_penetrating_fraction);
      EXPECT_LE(q.penetration->max_penetrating_fraction, 1.0);
      EXPECT_GE(q.penetration->max_penetration_mm, 0.0);
      if (q.penetration->max_penetrating_fraction == 0) EXPECT_EQ(q.penetration->max_penetration_mm, 0.0);
      ASSERT_TRUE(q.mean);
      EXPECT_GE(q.max_positive_energy, q.positive_energy);
      EXPECT_NEAR(q.positive_energy, positive_energy(*q.mean), 1e-12 * (1 + q.positive_energy));
      mean_fraction += q.penetration->penetrating_fraction / double(expected);
      max_fraction = std::max(max_fraction, q.penetration->max_penetrating_fraction);
      max_mm = std::max(max_mm, q.penetration->max_penetration_mm);
    }
    EXPECT_NEAR(m.penetration->penetrating_fraction, mean_fraction, 1e-12);
    EXPECT_EQ(m.penetration->max_penetrating_fraction, max_fraction);
    EXPECT_EQ(m.penetration->max_penetration_mm, max_mm);
    EXPECT_GE(m.penetration->max_edges_through, 0);  // measured on every frame
    EXPECT_LE(m.penetration->frames_with_edges_through, m.penetration->frames);
  }
  const std::string json = format_json(levels), table = format_table(levels), csv = format_csv(levels);
  const nlohmann::json report = nlohmann::json::parse(json);  // valid JSON: no nan
  for (const auto& [name, method] : report.at("levels")[0].at("methods").items()) {
    for (const char* key : {"penetrating_fraction", "max_penetrating_fraction", "max_penetration_mm",
                            "max_edges_through", "edges_through_frames", "body_self_crossing_frames"})
      EXPECT_TRUE(method.contains(key) && method.at(key).is_number()) << name << " " << key << "\n" << json;
    ASSERT_FALSE(method.at("sequences").empty()) << name;
    EXPECT_EQ(method.at("sequences")[0].at("body"), "mannequin") << name;
    for (const auto& sequence : method.at("sequences"))
      for (const char* key : {"positive_energy", "max_positive_energy", "penetrating_fraction"})
        EXPECT_TRUE(sequence.contains(key)) << name << " " << key << "\n" << sequence;
  }
  EXPECT_NE(table.find("Inside %"), std::string::npos) << table;
  EXPECT_NE(table.find("Depth max mm"), std::string::npos) << table;
  EXPECT_NE(table.find("Edges thru max"), std::string::npos) << table;
  EXPECT_NE(csv.find(",Pb4U,"), std::string::npos);
  EXPECT_NE(csv.find(",max_penetration_mm,"), std::string::npos) << csv;
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "level,triangles,vertices,method,K,term,value,diverged,diverged_at_frame");
}

TEST(Stability, EvaluateSelectsMotionsBySplit) {
  auto count = [](const std::string& split) {
    auto levels = evaluate(tiny_eval({"levels=[1]", "max_frames=1", "garments=[tshirt]", "split=" + split}),
                           {{"Pb4U", &shipped()}});
    return levels[0].methods[0].per_sequence;
  };
  const auto test = count("test"), train = count("train");
  ASSERT_FALSE(test.empty());
  ASSERT_FALSE(train.empty());
  for (const auto& q : test)
    for (const auto& p : train) EXPECT_NE(q.motion, p.motion);
  // The default is the test split.
  EXPECT_EQ(tiny_eval({}).split, "test");
  const std::string why = error_of([&] { count("heldout_nowhere"); });
  EXPECT_NE(why.find("no motion of split 'heldout_nowhere'"), std::string::npos) << why;
}

TEST(Stability, EvaluateKeepsOnlyTheListedMotions) {
  auto run = [](const std::vector<std::string>& sets) {  // later sets override the defaults
    std::vector<std::string> all{"levels=[1]", "max_frames=1", "garments=[tshirt]", "split=train", "max_sequences=0"};
    all.insert(all.end(), sets.begin(), sets.end());
    return evaluate(tiny_eval(all), {{"Pb4U", &shipped()}})[0].methods[0].per_sequence;
  };
  const auto all = run({});
  ASSERT_GE(all.size(), 2u);
  const std::string chosen = all.back().motion;
  const auto only = run({"motions=[" + chosen + "]"});
  ASSERT_EQ(only.size(), 1u);
  EXPECT_EQ(only[0].motion, chosen);
  // A name that is not a motion of the split is an error that names it, not an empty run.
  const std::string test_motion = run({"split=test"}).at(0).motion;
  for (const std::string& name : {std::string("no_such_motion"), test_motion}) {
    const std::string why = error_of([&] { run({"motions=[" + name + "]"}); });
    EXPECT_NE(why.find("motions: '" + name + "' is not a motion of split 'train'"), std::string::npos) << why;
  }
  // Without a body no motion is followed, so naming one is an error rather than ignored.
  const std::string why = error_of([&] {
    evaluate(tiny_eval({"effects=[gravity, pins]", "pins.top_band=0.02", "max_frames=3", "motions=[" + chosen + "]"}),
             {{"Pb4U", &shipped()}});
  });
  EXPECT_NE(why.find("motions: without a body"), std::string::npos) << why;
}

TEST(Stability, BodylessEvaluationHangsEachGarmentFromItsTopBand) {
  const EvalConfig config =
      tiny_eval({"levels=[1]", "max_frames=3", "effects=[gravity, pins]", "pins.top_band=0.02"});
  auto levels = evaluate(config, {{"Pb4U", &shipped()}, {"Reference", nullptr}});
  for (const MethodResult& m : levels[0].methods) {
    ASSERT_EQ(m.per_sequence.size(), 2u);  // tiny.yaml's t-shirt and skirt, once each, from rest
    for (const SequenceResult& q : m.per_sequence) {
      EXPECT_EQ(q.motion, "rest");
      EXPECT_FALSE(q.penetration);
    }
    EXPECT_FALSE(m.penetration);
  }
  const nlohmann::json report = nlohmann::json::parse(format_json(levels));
  for (const auto& [name, method] : report.at("levels")[0].at("methods").items()) {  // no penetration keys
    std::vector<nlohmann::json> holders{method};
    for (const auto& sequence : method.at("sequences")) holders.push_back(sequence);
    for (const auto& holder : holders)
      for (const auto& [key, value] : holder.items())
        EXPECT_EQ(key.find("penetrat"), std::string::npos) << name << ": " << key;
  }
  EXPECT_EQ(format_table(levels).find("Inside"), std::string::npos);
  // Each rule is required: a pinned set, and a length without a motion.
  std::string why = error_of([&] { evaluate(tiny_eval({"effects=[gravity, pins]", "max_frames=3"}), {{"P", &shipped()}}); });
  EXPECT_NE(why.find("pins.top_band"), std::string::npos) << why;
  why = error_of([&] {
    evaluate(tiny_eval({"effects=[gravity, pins]", "pins.top_band=0.02", "max_frames=0"}), {{"P", &shipped()}});
  });
  EXPECT_NE(why.find("max_frames"), std::string::npos) << why;
}

// Two frames of the tiny dataset's garment on its body, no meshes or plot written.
SceneConfig two_frames_on_the_tiny_body() {
  SceneConfig s;
  s.frames = 2;
  s.garment.dataset = test::tiny_dataset();
  s.body.dataset = test::tiny_dataset();
  s.outputs.mesh_format = "none";
  s.outputs.plot = false;
  return s;
}

TEST(Stability, SimulateWritesPenetrationColumnsWithABody) {
  SceneConfig s = two_frames_on_the_tiny_body();
  const std::string out = test::temp_dir("sim_penetration");
  SimulateResult r = simulate(s, "scene.yaml", &shipped(), out);
  ASSERT_EQ(r.frames, 3);
  std::ifstream csv(out + "/energies.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header,
            "frame,stretch,bending,collision,inertia,gravity,friction,total,residual_mm,penetrating_fraction,"
            "max_penetration_mm,edges_through_body,body_self_crossing_faces");
  const auto rows = test::read_csv(out + "/energies.csv");
  ASSERT_EQ(rows.size(), 4u);  // the header and frames 0-2
  const size_t edges = rows[0].size() - 2, crossing = rows[0].size() - 1;
  EXPECT_EQ(rows[1][edges], "nan");  // frame 0: not computed
  EXPECT_EQ(rows[1][crossing], "nan");
  int through = 0, frames_with = 0, crossing_frames = 0, crossing_most = 0;
  for (size_t i = 2; i < rows.size(); ++i) {
    for (const size_t c : {edges, crossing}) {
      EXPECT_NE(rows[i][c], "nan") << i;
      EXPECT_GE(std::stod(rows[i][c]), 0) << i;
    }
    through = std::max(through, int(std::stod(rows[i][edges])));
    frames_with += std::stod(rows[i][edges]) > 0;
    crossing_most = std::max(crossing_most, int(std::stod(rows[i][crossing])));
    crossing_frames += std::stod(rows[i][crossing]) > 0;
  }
  EXPECT_EQ(r.edges_through_max, through);  // the summary agrees with the rows
  EXPECT_EQ(r.edges_through_frames, frames_with);
  EXPECT_EQ(r.body_self_crossing_max, crossing_most);
  EXPECT_EQ(r.body_self_crossing_frames, crossing_frames);
}

TEST(Stability, TheResidualIsMeasuredEachFrameUnlessSwitchedOff) {
  SceneConfig s = two_frames_on_the_tiny_body();
  s.outputs.preview = false;
  for (const bool on : {true, false}) {
    s.outputs.residual = on;
    const std::string out = test::temp_dir("sim_residual");
    const SimulateResult r = simulate(s, "scene.yaml", &shipped(), out);
    ASSERT_EQ(r.frames, 3);
    EXPECT_EQ(r.residual_measured, on);
    const auto rows = test::read_csv(out + "/energies.csv");
    ASSERT_EQ(rows.size(), 4u);
    const size_t column = size_t(std::find(rows[0].begin(), rows[0].end(), "residual_mm") - rows[0].begin());
    ASSERT_LT(column, rows[0].size());
    for (size_t f = 2; f < rows.size(); ++f) {
      const double residual = std::stod(rows[f][column]);
      if (on)
        EXPECT_TRUE(std::isfinite(residual) && residual >= 0) << rows[f][column];
      else
        EXPECT_TRUE(std::isnan(residual)) << rows[f][column];
    }
  }
}

TEST(Stability, TheIntersectionFreeSolverReportsPerFrameTheClothItLeftOutOfContact) {
  SceneConfig s = two_frames_on_the_tiny_body();
  s.outputs.preview = false;
  s.physics.solver.contact = "barrier";
  const std::string out = test::temp_dir("sim_barrier");
  SimulateResult r = simulate(s, "scene.yaml", nullptr, out);
  ASSERT_EQ(r.frames, 3);
  EXPECT_TRUE(r.barrier_contact);
  const auto rows = test::read_csv(out + "/energies.csv");
  ASSERT_EQ(rows.size(), 4u);
  const std::vector<std::string> tail(rows[0].end() - 3, rows[0].end());
  EXPECT_EQ(tail, (std::vector<std::string>{"contact_excluded", "caught_by_body", "body_lag_mm"}));
  int frames_with_excluded = 0, most = 0;
  for (size_t f = 2; f < rows.size(); ++f) {  // frames 1 and 2 (row 1 is the start frame)
    const double excluded = std::stod(rows[f][rows[f].size() - 3]);
    EXPECT_GE(excluded, 0);
    EXPECT_EQ(excluded, std::floor(excluded));  // a count
    frames_with_excluded += excluded > 0;
    most = std::max(most, int(excluded));
  }
  EXPECT_EQ(r.excluded_frames, frames_with_excluded);  // the summary agrees with the rows
  EXPECT_EQ(r.excluded_max, most);
  // The penalty solver's file has no such columns.
  s.physics.solver.contact = "penalty";
  const SimulateResult p = simulate(s, "scene.yaml", nullptr, out + "/penalty");
  EXPECT_FALSE(p.barrier_contact);
  EXPECT_EQ(test::read_csv(out + "/penalty/energies.csv")[0].back(), "body_self_crossing_faces");
}

TEST(Stability, MethodPenaltyRunsThePenaltySolverWhateverTheScenesContact) {
  const std::string dir = test::temp_dir("sim_method_penalty");
  test::write_file(dir + "/s.yaml", "frames: 2\ngarment: {dataset: " + test::tiny_dataset() +
                                        "}\nbody: {dataset: " + test::tiny_dataset() +
                                        "}\nphysics: {solver: {contact: barrier}}\n"
                                        "outputs: {mesh_format: none, plot: false, preview: false}\n");
  for (const std::string method : {"reference", "penalty"}) {
    auto r = test::run_pb4u("-q simulate --method " + method + " --scene " + dir + "/s.yaml --out " + dir + "/" + method);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  EXPECT_EQ(test::read_csv(dir + "/reference/energies.csv")[0].back(), "body_lag_mm");  // barrier, as the scene says
  EXPECT_EQ(test::read_csv(dir + "/penalty/energies.csv")[0].back(), "body_self_crossing_faces");
}

TEST(Stability, SimulateStopsOnTheEnergyGuardFromTheCommandLine) {
  const std::string out = test::temp_dir("sim_energy_guard");
  // Ratio 1 over a floor of ~0: any frame whose positive energy exceeds frame 1's stops it;
  // a cloth falling into its pins stretches more every frame.
  auto r = test::run_pb4u("-q --threads 1 simulate --method reference --scene " + kSource +
                          "/configs/scenes/hanging_cloth.yaml --set garment.resolution=6 --frames 6 --format none"
                          " --set divergence.energy_ratio=1 --set divergence.energy_floor=1e-12 --out " + out);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("diverged at frame 2: positive energy"), std::string::npos) << r.err;
  EXPECT_EQ(read_pc2(out + "/garment.pc2").size(), 3u);  // frames 0, 1 and the tripping frame 2
  r = test::run_pb4u("-q simulate --method reference --scene " + kSource +
                     "/configs/scenes/hanging_cloth.yaml --set divergence.energy_ratio=0.5 --out " + out + "/x");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("divergence.energy_ratio"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace pb4u

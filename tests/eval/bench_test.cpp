// `pb4u bench` on the tiny dataset with the shipped models: the SPEC 7 CSV has its exact
// header, one row per level and method, finite values; fixed-K rows carry their K; the stage
// table is finite; the no-body variant builds no world edges. No timing is
// asserted (the CI machine is shared). Plus the exponent fit in closed form and bad configs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>

#include "pb4u/eval/bench.h"
#include "pb4u/eval/bench_writers.h"
#include "pb4u/model/model_file.h"
#include "eval/eval_test_util.h"
#include "test_util.h"

namespace pb4u {
namespace {
namespace fs = std::filesystem;

using test::kSource;
using test::read_csv;

std::string bench_args(const std::string& out, const std::string& extra = "") {
  return "-q --threads 1 bench --config " + kSource + "/configs/bench/tiny.yaml --set dataset=" +
         test::tiny_dataset() + " --set checkpoints=[" + kSource + "/data/pretrained/pb4u.h5," + kSource +
         "/data/pretrained/mgn.h5] --set frames=3 --set stage_repeats=1 --out " + out + " " + extra;
}

// Without Blender the rows are skipped with one log line; `enabled: on` makes it an error.
TEST(BenchBlender, MissingBlenderSkipsTheRowsOrFailsWhenRequired) {
  const std::string out = test::temp_dir("bench_noblender");
  const std::string few = "--set levels=[1] --set k_values=[] --set ablations=[] --set no_body_variant=false ";
  auto r = test::run_pb4u(bench_args(out, few + "--set blender.enabled=auto --set blender.executable=no-such-blender")
                              .replace(0, 3, ""));  // not quiet: the log line is the point
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("Blender ('no-such-blender') not found on PATH: no Blender rows"), std::string::npos) << r.err;
  EXPECT_EQ(test::read_file(out + "/bench.csv").find("Blender"), std::string::npos);
  auto on = test::run_pb4u(bench_args(out + "/on", few + "--set blender.enabled=on --set blender.executable=no-such-blender"));
  EXPECT_EQ(on.exit_code, 1);
  EXPECT_NE(on.err.find("blender.executable: 'no-such-blender' not found"), std::string::npos) << on.err;
}

// With Blender installed: one Blender row per level and quality, scored with pb4u's terms.
TEST(BenchBlender, BlenderRowsAreScoredWithPb4uTerms) {
  if (find_blender("blender").empty()) GTEST_SKIP() << "Blender is not installed (scripts/install_deps.sh --blender)";
  const std::string out = test::temp_dir("bench_blender");
  auto r = test::run_pb4u(bench_args(out, "--set levels=[1] --set k_values=[] --set ablations=[] "
                                          "--set no_body_variant=false --set blender.enabled=on "
                                          "--set blender.qualities=[2]"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = read_csv(out + "/bench_details.csv");
  int blender = 0;
  for (size_t i = 1; i < rows.size(); ++i) {
    if (rows[i][3] != "Blender (quality 2)") continue;
    ++blender;
    EXPECT_EQ(rows[i][4], "blender");
    for (size_t c = 8; c < 11; ++c) EXPECT_TRUE(std::isfinite(std::stod(rows[i][c]))) << rows[0][c];
  }
  EXPECT_EQ(blender, 1);
  EXPECT_NE(test::read_file(out + "/table.txt").find("Networks vs Blender's cloth at equal loss"), std::string::npos);
}

TEST(Bench, TinyConfigWritesSpecCsvWithFiniteValues) {
  const std::string out = test::temp_dir("bench");
  auto r = test::run_pb4u(bench_args(out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = read_csv(out + "/bench.csv");
  ASSERT_FALSE(rows.empty());
  const std::vector<std::string> header{"level", "triangles", "vertices", "method", "K", "threads",
                                        "latency_ms_median", "latency_ms_min", "physics_loss"};
  EXPECT_EQ(rows[0], header);
  // tiny.yaml: 2 levels x (2 checkpoints + 2 fixed K + 1 ablation + 2 reference (penalty and
  // barrier contact) + 2 refined (each checkpoint) + 2 refined to a tolerance + 2 no-body).
  ASSERT_EQ(rows.size(), 1u + 2u * 13u);
  // The shipped Pb4U's name follows its inference switches ("Pb4U + projection").
  const std::string pb4u = method_name(load_model_file(kSource + "/data/pretrained/pb4u.h5").config);
  ASSERT_EQ(pb4u.rfind("Pb4U", 0), 0u) << pb4u;
  std::map<std::string, int> per_method;
  std::vector<int64_t> fixed_k;
  for (size_t i = 1; i < rows.size(); ++i) {
    const auto& c = rows[i];
    ASSERT_EQ(c.size(), header.size()) << "row " << i;
    EXPECT_TRUE(c[0] == "1" || c[0] == "3");
    EXPECT_GT(std::stoll(c[1]), 0);
    EXPECT_GT(std::stoll(c[2]), 0);
    EXPECT_EQ(c[5], "1");  // --threads 1
    const double median = std::stod(c[6]), min = std::stod(c[7]), loss = std::stod(c[8]);
    EXPECT_TRUE(std::isfinite(median) && median > 0) << c[3];
    EXPECT_TRUE(std::isfinite(min) && min > 0 && min <= median) << c[3];
    EXPECT_TRUE(std::isfinite(loss)) << c[3];
    ++per_method[c[3]];
    if (c[3] == pb4u + " (fixed K)") fixed_k.push_back(std::stoll(c[4]));
    if (c[3] == "MGN" || c[3].rfind("Reference", 0) == 0) EXPECT_EQ(c[4], "0") << c[3];
  }
  EXPECT_EQ(per_method[pb4u], 2);
  EXPECT_EQ(per_method["MGN"], 2);
  EXPECT_EQ(per_method["Reference (2 it)"], 2);
  EXPECT_EQ(per_method["Reference barrier (2 it)"], 2);  // the intersection-free contact
  EXPECT_EQ(per_method[pb4u + " + 2 it"], 2);  // refined by the solver
  EXPECT_EQ(per_method["MGN + 2 it"], 2);      // and MGN the same way
  EXPECT_EQ(per_method[pb4u + " + to 1 mm"], 2);  // refined until the solver's step is under 1 mm
  EXPECT_EQ(per_method["MGN + to 1 mm"], 2);
  EXPECT_EQ(per_method[pb4u + " (no body)"], 2);
  EXPECT_EQ(per_method["Reference (2 it) (no body)"], 2);
  EXPECT_EQ(fixed_k, (std::vector<int64_t>{0, 2, 0, 2}));

  const auto stages = read_csv(out + "/stages.csv");
  ASSERT_EQ(stages.size(), 1u + 2u * 3u);  // Pb4U, MGN, Pb4U (no body) per level
  for (size_t i = 1; i < stages.size(); ++i) {
    for (size_t j = 7; j < stages[i].size(); ++j)
      EXPECT_TRUE(std::isfinite(std::stod(stages[i][j]))) << stages[0][j] << " of " << stages[i][4];
    if (stages[i][5] == "false") {  // without a body: no world edges, no world-edge query
      EXPECT_EQ(stages[i][3], "0");
      EXPECT_EQ(std::stod(stages[i][8]), 0.0);
    } else {
      EXPECT_GT(std::stoll(stages[i][3]), 0) << "the tiny scene's garment touches the body";
    }
  }
  const std::string table = test::read_file(out + "/table.txt");
  EXPECT_NE(table.find("Lv.3"), std::string::npos);
  EXPECT_NE(table.find("Networks vs the reference solver (penalty contact) at equal loss"), std::string::npos);
  EXPECT_NE(table.find("Networks vs the reference solver (intersection-free contact) at equal loss"), std::string::npos);
  EXPECT_TRUE(fs::exists(out + "/bench_config.yaml"));
}

// minimum_every: every row's residual median, and on the sampled frames the distance to the
// minimum, in bench_details.csv and the table. (The reference's own steps need not read 0: on a
// frame where it left cloth out of contact the minimum lies elsewhere, docs/evaluation.md.)
TEST(Bench, MinimumEveryPutsTheDistanceToTheMinimumBesideTheResidual) {
  const std::string out = test::temp_dir("bench_minimum");
  auto r = test::run_pb4u(bench_args(out, "--set levels=[1] --set checkpoints=[" + kSource +
                                              "/data/pretrained/pb4u.h5] --set k_values=[] --set ablations=[] "
                                              "--set reference_iterations=[200] --set reference_contacts=[barrier] "
                                              "--set refine_iterations=[] --set refine_tolerances_mm=[] "
                                              "--set no_body_variant=false --set frames=4 --set minimum_every=2"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = read_csv(out + "/bench_details.csv");
  ASSERT_EQ(rows.size(), 3u);  // the network and the reference
  auto column = [&](const std::string& name) {
    const size_t c = std::find(rows[0].begin(), rows[0].end(), name) - rows[0].begin();
    EXPECT_LT(c, rows[0].size()) << name;
    return c;
  };
  const size_t method = column("method"), residual = column("residual_mm_median"),
               distance = column("distance_to_minimum_mm_median"), largest = column("distance_to_minimum_mm_max"),
               gap = column("energy_gap_j_median");
  for (size_t i = 1; i < rows.size(); ++i) {
    ASSERT_GT(rows[i].size(), gap) << rows[i][method];
    EXPECT_TRUE(std::isfinite(std::stod(rows[i][residual]))) << rows[i][method];
    EXPECT_LE(std::stod(rows[i][distance]), std::stod(rows[i][largest])) << rows[i][method];
    EXPECT_GE(std::stod(rows[i][distance]), 0.0) << rows[i][method];
    EXPECT_TRUE(std::isfinite(std::stod(rows[i][gap]))) << rows[i][method];
    if (rows[i][method].rfind("Reference", 0) != 0) {
      EXPECT_GT(std::stod(rows[i][distance]), 1.0) << "mm: the network's step is not at its minimum";
      EXPECT_GT(std::stod(rows[i][gap]), 0.0) << "J: lower there";
    }
  }
  EXPECT_NE(test::read_file(out + "/table.txt").find("to min. mm"), std::string::npos);
}

// bench_details.csv has a column per term, the repulsion term's (effect self_collision) among
// them, empty where a row has no such term.
TEST(Bench, DetailsCsvHasAColumnPerTermRepulsionIncluded) {
  BenchResult result;
  BenchRow with, without;
  with.method = "CCRAFT";
  with.terms = {{"stretch", 0.25}, {"repulsion", 0.5}};
  without.method = "Pb4U";
  without.terms = {{"stretch", 0.125}};
  result.rows = {with, without};
  std::istringstream in(format_bench_details_csv(result));
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::stringstream cs(line);
    for (std::string cell; std::getline(cs, cell, ',');) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.push_back("");
    rows.push_back(cells);
  }
  ASSERT_EQ(rows.size(), 3u);
  const auto column = std::find(rows[0].begin(), rows[0].end(), "repulsion") - rows[0].begin();
  ASSERT_LT(static_cast<size_t>(column), rows[0].size());
  EXPECT_EQ(rows[1][static_cast<size_t>(column)], "0.5");
  EXPECT_EQ(rows[2][static_cast<size_t>(column)], "");
  const auto stretch = std::find(rows[0].begin(), rows[0].end(), "stretch") - rows[0].begin();
  EXPECT_EQ(rows[2][static_cast<size_t>(stretch)], "0.125");
}

TEST(Bench, LatencyExponentIsTheLogLogSlope) {
  std::vector<BenchRow> rows;
  for (int64_t v : {100, 400, 1600, 6400}) {
    BenchRow r;
    r.method = "m";
    r.vertices = v;
    r.latency_ms_median = 0.02 * std::pow(double(v), 1.5);
    rows.push_back(r);
  }
  EXPECT_NEAR(latency_exponent(rows, "m"), 1.5, 1e-12);
  EXPECT_TRUE(std::isnan(latency_exponent(rows, "other")));
}

TEST(Bench, EqualLossTakesTheFastestFinishedRunAtOrBelowTheNetworksLoss) {
  auto row = [](int level, const std::string& method, const std::string& family, double ms, double loss,
                bool diverged = false) {
    BenchRow r;
    r.level = level;
    r.method = method;
    r.family = family;
    r.latency_ms_median = ms;
    r.positive_loss = loss;
    r.physics_loss = loss + 1.0;  // gravity's share, the same for every method: not compared
    r.diverged = diverged;
    return r;
  };
  std::vector<BenchRow> rows = {
      row(1, "Net", "network", 10, 2.0),
      row(1, "Reference (1 it)", "reference", 20, 1.5, /*diverged=*/true),  // low loss, stopped early
      row(1, "Reference (10 it)", "reference", 100, 2.5),                   // above the network's loss
      row(1, "Reference (30 it)", "reference", 300, 1.9),
      row(1, "Reference (100 it)", "reference", 900, 1.2),
      row(2, "Reference (3 it)", "reference", 50, 1.0),  // another level
      row(1, "Blender (quality 5)", "blender", 40, 30.0)};
  const BenchRow* best = cheapest_at_equal_loss(rows, rows[0], "reference");
  ASSERT_NE(best, nullptr);
  EXPECT_EQ(best->method, "Reference (30 it)");
  EXPECT_EQ(cheapest_at_equal_loss(rows, rows[0], "blender"), nullptr);
}

TEST(Bench, BadConfigsFailWithTheKey) {
  const std::string out = test::temp_dir("bench_bad");
  auto r = test::run_pb4u(bench_args(out, "--set ablations=[no_such]"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("ablations"), std::string::npos) << r.err;
  r = test::run_pb4u(bench_args(out, "--set garment=cape"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("garment"), std::string::npos) << r.err;
  r = test::run_pb4u(bench_args(out, "--set reference_contacts=[springs]"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("reference_contacts"), std::string::npos) << r.err;
  r = test::run_pb4u(bench_args(out, "--set reference_iterations=[0]"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("reference_iterations"), std::string::npos) << r.err;
  r = test::run_pb4u(bench_args(out, "--set refine_tolerances_mm=[0]"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("refine_tolerances_mm"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out + "/bench.csv"));
}

}  // namespace
}  // namespace pb4u

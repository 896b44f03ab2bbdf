// `pb4u score`: scoring simulate's own output reproduces its energies.csv; a hand-made PC2 of
// a uniformly stretched cloth gives the closed-form StVK energy; files in any vertex order
// source (OBJ, PLY, PC2, rollout.h5) read back in file order; bad inputs fail in one line.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "pb4u/eval/score.h"
#include "pb4u/io/frame_sequence.h"
#include "pb4u/io/mesh_io.h"
#include "pb4u/io/point_cache.h"
#include "pb4u/io/preview.h"
#include "pb4u/sim/simulate.h"
#include "pb4u/util/error.h"
#include "eval/eval_test_util.h"
#include "test_util.h"

namespace pb4u {
namespace {

namespace fs = std::filesystem;
using test::kSource;
using test::read_csv;

// A solver rollout's energies.csv without the intersection-free solver's own account of each
// step (cloth left out of barrier contact, the body's lag): score reads frames, not a solve.
std::vector<std::vector<std::string>> without_solver_columns(std::vector<std::vector<std::string>> rows) {
  static const std::vector<std::string> solver_only = {"contact_excluded", "caught_by_body", "body_lag_mm"};
  if (rows.empty()) return rows;
  std::vector<size_t> keep;
  for (size_t c = 0; c < rows[0].size(); ++c)
    if (std::find(solver_only.begin(), solver_only.end(), rows[0][c]) == solver_only.end()) keep.push_back(c);
  for (auto& row : rows) {
    std::vector<std::string> kept;
    for (size_t c : keep)
      if (c < row.size()) kept.push_back(row[c]);
    row = std::move(kept);
  }
  return rows;
}

// Per row of a solver rollout's energies.csv: whether the solver left cloth out of barrier
// contact on that frame. There its residual is measured with the vertices it left out
// (step_residual.h), which score, reading frames and not a solve, cannot know: score decides
// who is free from the frame alone and reads another objective.
std::vector<bool> rows_with_cloth_left_out(const std::vector<std::vector<std::string>>& rows) {
  std::vector<bool> out(rows.size(), false);
  if (rows.empty()) return out;
  const auto column = std::find(rows[0].begin(), rows[0].end(), "contact_excluded");
  if (column == rows[0].end()) return out;
  const size_t c = size_t(column - rows[0].begin());
  for (size_t r = 1; r < rows.size(); ++r)
    out[r] = c < rows[r].size() && rows[r][c] != "nan" && std::stod(rows[r][c]) > 0;
  return out;
}

// The frames whose residuals were compared (those where the solver left no cloth out).
int expect_same_csv(const std::string& expected_path, const std::string& actual_text) {
  const std::string actual_path = expected_path + ".score.csv";
  test::write_file(actual_path, actual_text);
  const auto full = read_csv(expected_path);
  const std::vector<bool> left_out = rows_with_cloth_left_out(full);
  const auto want = without_solver_columns(full), got = read_csv(actual_path);
  int residuals_compared = 0;
  EXPECT_EQ(want.size(), got.size());
  EXPECT_GE(want.size(), 3u);
  if (want.size() != got.size() || want.size() < 3) return -1;
  EXPECT_EQ(want[0], got[0]);  // the same columns
  for (size_t r = 1; r < want.size(); ++r) {
    EXPECT_EQ(want[r].size(), got[r].size()) << "row " << r;
    if (want[r].size() != got[r].size()) return -1;
    for (size_t c = 0; c < want[r].size(); ++c) {
      if (want[r][c] == "nan") {
        EXPECT_EQ(got[r][c], "nan") << "row " << r << " " << want[0][c];
        continue;
      }
      const double a = std::stod(want[r][c]), b = std::stod(got[r][c]);
      if (want[0][c] == "residual_mm") {
        if (left_out[r]) {
          EXPECT_TRUE(std::isfinite(b)) << "row " << r << " residual_mm";
          continue;
        }
        ++residuals_compared;
      }
      EXPECT_LE(std::abs(a - b), 1e-6 * std::max(std::abs(a), 1e-12)) << "row " << r << " " << want[0][c];
    }
  }
  return residuals_compared;
}

// A t-shirt of the tiny dataset on its body, rolled out by the reference solver (its contact:
// barrier, the default, or penalty).
std::string simulated_walk(const std::string& tag, const std::string& contact = "barrier") {
  SceneConfig s;
  s.physics.solver.contact = contact;
  s.frames = 4;
  s.garment.dataset = test::tiny_dataset();
  s.body.dataset = test::tiny_dataset();
  s.outputs.plot = false;
  const std::string out = test::temp_dir(tag);
  test::write_file(out + "/scene.yaml", config_to_yaml(s));
  SimulateResult r = simulate(s, out + "/scene.yaml", nullptr, out + "/sim");
  EXPECT_FALSE(r.diverged);
  return out;
}

TEST(Score, SimulatesOwnOutputReproducesItsEnergiesCsv) {
  const std::string dir = simulated_walk("score_sim");
  const std::string sim = dir + "/sim";
  // In process, from rollout.h5 (rest shape, previous frame and body included).
  FrameSequence g = read_frame_sequence(sim + "/rollout.h5", "garment");
  FrameSequence b = read_frame_sequence(sim + "/rollout.h5", "body");
  ASSERT_EQ(g.frames.size(), 5u);
  ASSERT_EQ(b.frames.size(), 5u);
  ASSERT_GT(g.rest.rows(), 0);
  ASSERT_GT(g.previous.rows(), 0);
  ScoreInput in;
  in.garment_rest = TriMesh{g.rest, g.faces};
  in.frames = g.frames;
  in.previous = g.previous;
  in.body = b.frames;
  in.body_faces = b.faces;
  in.effects = Effects::from_names({"gravity", "collision", "friction"}, "test");
  expect_same_csv(sim + "/energies.csv", score_csv(score_sequence(in)));
  // The tiny body leaves some cloth no free place on every frame, so the barrier solver's
  // residuals are its own (above); the penalty solver's are compared on every frame.
  const std::string penalty_dir = simulated_walk("score_sim_penalty", "penalty");
  FrameSequence gp = read_frame_sequence(penalty_dir + "/sim/rollout.h5", "garment");
  ScoreInput penalty = in;
  penalty.frames = gp.frames;
  penalty.previous = gp.previous;
  penalty.physics.solver.contact = "penalty";
  EXPECT_EQ(expect_same_csv(penalty_dir + "/sim/energies.csv", score_csv(score_sequence(penalty))), 4);

  // Through the binary, with the scene supplying material and effects.
  auto run = test::run_pb4u("-q score --frames " + sim + "/rollout.h5 --scene " + dir + "/scene.yaml --format csv");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  expect_same_csv(sim + "/energies.csv", run.out);

  // The OBJ sequence and the PC2 caches with the rest mesh and the previous frame as files:
  // the same figures from frame 2 on (OBJ keeps 9 digits, PC2 float32: looser).
  auto obj = test::run_pb4u("-q score --frames '" + sim + "/garment_%04d.obj' --garment " + sim +
                            "/garment_rest.obj --body-frames '" + sim + "/body_*.obj' --format json");
  ASSERT_EQ(obj.exit_code, 0) << obj.err;
  const nlohmann::json scored = nlohmann::json::parse(obj.out);
  EXPECT_EQ(scored.at("scored_frames"), 4) << obj.out;
  EXPECT_TRUE(scored.contains("penetrating_fraction")) << obj.out;
  auto pc2 = test::run_pb4u("-q score --frames " + sim + "/garment.pc2 --garment " + sim + "/garment_rest.obj " +
                            "--body-frames " + sim + "/body.pc2 --body " + sim + "/body_0000.obj --format csv");
  ASSERT_EQ(pc2.exit_code, 0) << pc2.err;
  const auto full = read_csv(sim + "/energies.csv");
  const bool frame4_left_out = rows_with_cloth_left_out(full)[4];
  const auto want = without_solver_columns(full);
  test::write_file(dir + "/pc2.csv", pc2.out);
  const auto got = read_csv(dir + "/pc2.csv");
  ASSERT_EQ(got.size(), want.size());
  ASSERT_EQ(got[0], want[0]);
  for (size_t c = 1; c < want[0].size(); ++c) {
    // Differences of float32 positions: inertia and friction read velocities; the residual of a
    // converged step (~1.4e-4 mm here) moves when its positions are rounded to float32, whose
    // half ulp at 1 m is 60 nm: by a few nm here, by 13 nm with LibTorch 2.11 on another CPU.
    if (want[0][c] == "inertia" || want[0][c] == "friction") continue;
    if (want[0][c] == "residual_mm") {
      if (!frame4_left_out)
        EXPECT_NEAR(std::stod(got[4][c]), std::stod(want[4][c]), 1e-4) << "residual_mm";  // 0.1 um
      continue;
    }
    const double a = std::stod(want[4][c]), b2 = std::stod(got[4][c]);
    EXPECT_NEAR(b2, a, 1e-3 * std::abs(a) + 1e-6) << want[0][c];
  }
}

// A flat n x n square (xz plane) stretched by s along x, held still over 3 frames: stretch is
// the closed form A h (mu + lambda/2) ((s^2 - 1)/2)^2, bending and inertia vanish.
TEST(Score, HandMadePointCacheOfAStretchedSquareGivesTheClosedFormStretch) {
  const std::string dir = test::temp_dir("score_square");
  const TriMesh rest = test::grid_mesh(4, 0.5);
  write_obj(dir + "/rest.obj", rest);
  const double s = 1.1;
  Eigen::MatrixXd stretched = rest.V;
  stretched.col(0) *= s;
  write_pc2(dir + "/square.pc2", {stretched, stretched, stretched});
  const Material m;  // SPEC 2 defaults
  const double g = (s * s - 1) / 2;
  const double expected = 0.25 * m.thickness * (m.mu + m.lambda / 2) * g * g;

  auto run = test::run_pb4u("-q score --frames " + dir + "/square.pc2 --garment " + dir + "/rest.obj --set 'effects=[]' --format json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  ScoreInput in;
  in.garment_rest = read_mesh_in_file_order(dir + "/rest.obj");
  in.frames = read_frame_sequence(dir + "/square.pc2").frames;
  in.effects = Effects::from_names({}, "test");
  const ScoreResult r = score_sequence(in);
  ASSERT_EQ(r.reports.size(), 2u);
  EXPECT_NEAR(r.mean.value("stretch"), expected, 1e-6 * expected);  // PC2 is float32
  EXPECT_NEAR(r.mean.value("bending"), 0, 1e-9);
  EXPECT_NEAR(r.mean.value("inertia"), 0, 1e-12);
  EXPECT_FALSE(r.mean.has("gravity"));
  const nlohmann::ordered_json scored = nlohmann::ordered_json::parse(run.out);  // keys in file order
  const auto& mean = scored.at("mean");
  ASSERT_FALSE(mean.empty()) << run.out;
  EXPECT_EQ(mean.begin().key(), "stretch") << run.out;  // the first term
  EXPECT_NEAR(mean.at("stretch").get<double>(), expected, 1e-6 * expected) << run.out;
  EXPECT_FALSE(mean.contains("gravity")) << run.out;
  for (const auto& frame : scored.at("per_frame")) EXPECT_FALSE(frame.contains("gravity")) << run.out;
}

TEST(Score, MeshesReadInFileOrderKeepTheirVertexOrder) {
  const std::string dir = test::temp_dir("score_order");
  // Vertex 0 is not used by the first face and a duplicate position exists: read_mesh would
  // weld and renumber, the file-order reader must not.
  test::write_file(dir + "/quad.obj",
                   "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 1 0 0\nvt 0 0\nf 2/1 3/1 4/1 1/1\n");
  const TriMesh m = read_mesh_in_file_order(dir + "/quad.obj");
  ASSERT_EQ(m.V.rows(), 5);
  ASSERT_EQ(m.F.rows(), 2);  // the quad fanned
  EXPECT_EQ(m.F(0, 0), 1);
  EXPECT_EQ(m.V(4, 0), 1.0);
  write_ply(dir + "/quad.ply", m);  // binary little-endian
  const TriMesh p = read_mesh_in_file_order(dir + "/quad.ply");
  EXPECT_TRUE(p.V.isApprox(m.V));
  EXPECT_EQ(p.F, m.F);
  test::write_file(dir + "/ascii.ply",
                   "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
                   "property double z\nproperty uchar red\nelement face 1\nproperty list uchar int vertex_indices\n"
                   "end_header\n0 0 0 255\n1 0 0 0\n0 0 1 7\n3 2 1 0\n");
  const TriMesh a = read_mesh_in_file_order(dir + "/ascii.ply");
  ASSERT_EQ(a.V.rows(), 3);
  EXPECT_EQ(a.V(2, 2), 1.0);
  EXPECT_EQ(a.F(0, 0), 2);
}

TEST(Score, BadInputsFailInOneLineNamingTheFile) {
  const std::string dir = test::temp_dir("score_bad");
  const TriMesh rest = test::grid_mesh(2, 0.5);  // 9 vertices
  write_obj(dir + "/rest.obj", rest);
  write_obj(dir + "/other.obj", test::grid_mesh(3, 0.5));  // 16
  write_pc2(dir + "/ok.pc2", {rest.V, rest.V, rest.V});
  write_pc2(dir + "/one.pc2", {rest.V});
  test::write_file(dir + "/junk.pc2", "POINTCACHE2\0garbage");
  std::vector<Eigen::MatrixXd> body2{rest.V, rest.V};
  write_pc2(dir + "/body2.pc2", body2);
  struct Case {
    std::string args, needle;
  };
  const std::vector<Case> cases{
      {"--frames " + dir + "/ok.pc2 --garment " + dir + "/other.obj", "9 vertices per frame, but the rest mesh"},
      {"--frames " + dir + "/junk.pc2 --garment " + dir + "/rest.obj", dir + "/junk.pc2"},
      {"--frames " + dir + "/missing.pc2 --garment " + dir + "/rest.obj", "missing.pc2: "},
      {"--frames " + dir + "/one.pc2 --garment " + dir + "/rest.obj", "at least 2"},
      {"--frames " + dir + "/ok.pc2", "no rest shape"},
      {"--frames " + dir + "/ok.pc2 --garment " + dir + "/rest.obj --body-frames " + dir + "/body2.pc2 --body " + dir +
           "/rest.obj",
       "2 body frames for 3 garment frames"},
      {"--frames " + dir + "/ok.pc2 --garment " + dir + "/rest.obj --body-frames " + dir + "/ok.pc2",
       "give the body mesh with --body"},
      {"--frames '" + dir + "/nothing_%04d.obj' --garment " + dir + "/rest.obj", "no file matches"},
      {"--frames " + dir + "/ok.pc2 --garment " + dir + "/rest.obj --set effects=[collision]", "need a body"},
  };
  for (const Case& c : cases) {
    auto run = test::run_pb4u("-q score " + c.args);
    EXPECT_EQ(run.exit_code, 1) << c.args;
    EXPECT_NE(run.err.find(c.needle), std::string::npos) << c.args << "\n" << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  }
}

TEST(Preview, FramesSpreadOverTheRolloutFirstAndLastIncluded) {
  EXPECT_EQ(preview_frames(61), (std::vector<int>{0, 20, 40, 60}));
  EXPECT_EQ(preview_frames(3), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(preview_frames(1), (std::vector<int>{0}));
  EXPECT_TRUE(preview_frames(0).empty());
}

// simulate writes preview.png (the rollout above has a body) unless told not to.
TEST(Preview, SimulateWritesAContactSheetUnlessOff) {
  const std::string dir = simulated_walk("preview_on");
  if (std::system("/usr/bin/python3 -c 'import matplotlib' 2>/dev/null") != 0)
    GTEST_SKIP() << "no matplotlib under /usr/bin/python3 (scripts/install_deps.sh installs it)";
  ASSERT_TRUE(fs::exists(dir + "/sim/preview.png"));
  std::ifstream png(dir + "/sim/preview.png", std::ios::binary);
  char magic[4] = {};
  png.read(magic, 4);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
  EXPECT_GT(fs::file_size(dir + "/sim/preview.png"), 10000u);  // panels, not an empty figure
  auto off = test::run_pb4u("-q simulate --method reference --scene " + kSource + "/configs/scenes/hanging_cloth.yaml"
                            " --set garment.resolution=6 --frames 2 --format none --preview off --out " + dir + "/off");
  ASSERT_EQ(off.exit_code, 0) << off.err;
  EXPECT_TRUE(fs::exists(dir + "/off/energies.csv"));
  EXPECT_FALSE(fs::exists(dir + "/off/preview.png"));
}

// evaluate --preview: the sheet of the first network's worst sequence.
TEST(Preview, EvaluateWritesTheWorstSequencesSheet) {
  if (std::system("/usr/bin/python3 -c 'import matplotlib' 2>/dev/null") != 0)
    GTEST_SKIP() << "no matplotlib under /usr/bin/python3 (scripts/install_deps.sh installs it)";
  const std::string dir = test::temp_dir("preview_eval");
  auto run = test::run_pb4u("--threads 1 evaluate --checkpoint " + kSource + "/data/pretrained/pb4u.h5 --config " +
                            kSource + "/configs/eval/tiny.yaml --set dataset=" + test::tiny_dataset() +
                            " --set levels=[1] --set max_frames=3 --preview " + dir + "/worst.png");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(fs::exists(dir + "/worst.png"));
  EXPECT_NE(run.err.find("worst sequence (positive energy mean"), std::string::npos) << run.err;
}

}  // namespace
}  // namespace pb4u

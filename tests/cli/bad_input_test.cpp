// Bad input of every kind the product reads (issue 9): missing, empty, truncated and
// random-byte meshes, BVH motions, YAML configs and scenes, HDF5 datasets, training
// checkpoints and exports, through every command that reads them; wrong config keys and
// types; a checkpoint that does not match its config; outputs that cannot be written. Each
// must fail with one line on stderr naming the file or key, exit 1, not crash, and leave
// what was there before untouched.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <random>

#include "test_util.h"

namespace pb4u {
namespace {
namespace fs = std::filesystem;

using test::kSource;
const std::string kExport = std::string(PB4U_TEST_DATA) + "/pretrained/pb4u.h5";
const std::string kBvh = std::string(PB4U_MOCAP_DATA) + "/cmu_131_01.bvh";
const std::string kMesh = std::string(PB4U_TEST_DATA) + "/meshes/tshirt.obj";

// `args` fails cleanly: exit 1, exactly one line "pb4u: error: ..." naming each of `names`
// (the file, and the key where there is one), no crash.
void expect_clean_failure(const std::string& args, const std::vector<std::string>& names, const std::string& what) {
  SCOPED_TRACE(what + ": pb4u " + args);
  test::CommandResult r = test::run_pb4u("-q " + args);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(r.err.rfind("pb4u: error: ", 0), 0u) << r.err;
  for (const auto& name : names)
    EXPECT_NE(r.err.find(name), std::string::npos) << "the error should name " << name << ": " << r.err;
}
void expect_clean_failure(const std::string& args, const std::string& name, const std::string& what) {
  expect_clean_failure(args, std::vector<std::string>{name}, what);
}

std::string read_bytes(const std::string& path) { return test::read_file(path); }

// The four broken versions of a good file: missing, empty, its first half, random bytes.
struct Broken {
  std::string name, path;
};
std::vector<Broken> broken_versions(const std::string& dir, const std::string& good, const std::string& ext) {
  const std::string bytes = read_bytes(good);
  std::mt19937 rng(static_cast<unsigned>(bytes.size()));
  std::string random(std::max<size_t>(512, std::min<size_t>(bytes.size(), 8192)), '\0');
  for (char& c : random) c = static_cast<char>(rng());
  std::vector<Broken> out{{"missing", dir + "/missing" + ext},
                          {"empty", dir + "/empty" + ext},
                          {"truncated", dir + "/truncated" + ext},
                          {"random bytes", dir + "/random" + ext}};
  test::write_file(out[1].path, "");
  test::write_file(out[2].path, bytes.substr(0, bytes.size() / 2));
  test::write_file(out[3].path, random);
  return out;
}

// A scene YAML of a square cloth (or a garment file) with no body: cheap to build.
std::string scene_file(const std::string& dir, const std::string& garment_file = "") {
  std::string text = "frames: 2\neffects: [gravity]\noutputs: {plot: false, mesh_format: none}\n";
  text += garment_file.empty() ? "garment: {source: square, resolution: 4}\n"
                               : "garment: {source: file, file: '" + garment_file + "'}\n";
  const std::string path = dir + "/scene.yaml";
  test::write_file(path, text);
  return path;
}

// A training checkpoint of the tiny config after one step, made once.
const std::string& tiny_run() {
  static const std::string out = [] {
    const std::string dir = test::temp_dir("badinput_run") + "/run";
    test::CommandResult r = test::run_pb4u("-q --threads 1 train --config " + kSource +
                                           "/configs/train/tiny.yaml --set run.steps=1 --set data.dataset=" +
                                           test::tiny_dataset() + " --out " + dir);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return dir;
  }();
  return out;
}

// Every broken version through the command that reads the kind first; the other commands
// share its loader and get the random bytes only (each launch of the binary costs a second).
TEST(BadInput, Meshes) {
  const std::string dir = test::temp_dir("bad_meshes");
  std::vector<Broken> files = broken_versions(dir, kMesh, ".obj");
  for (const auto& b : files) expect_clean_failure("inspect " + b.path, b.path, "mesh " + b.name);
  expect_clean_failure("simulate --method reference --scene " + scene_file(dir, files[3].path) + " --out " + dir + "/o",
                       files[3].path, "garment mesh of random bytes");
  // PLY headers assimp would spin on or abort in (found by mesh_fuzz), refused up front.
  const std::string header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n";
  const std::string rest = "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n";
  const std::string body = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const std::vector<std::pair<std::string, std::string>> plys{
      {header + rest, "no end_header"},
      {header + rest + body, "unknown keyword '0'"},  // data where the header should end
      {std::string(header).replace(header.find("vertex 3"), 8, "vertex 3000000000") + rest + "end_header\n" + body,
       "3000000000 vertex elements"},
      {header + "prperty float y\n" + "end_header\n" + body, "unknown keyword"},
      {header + "element face 1\nproperty list uchar int vertex_indices\nend_header\n" + body, "no 'y' property"}};
  for (size_t k = 0; k < plys.size(); ++k) {
    const std::string path = dir + "/header" + std::to_string(k) + ".ply";
    test::write_file(path, plys[k].first);
    expect_clean_failure("inspect " + path, {path, plys[k].second}, "PLY header " + plys[k].second);
  }
  // assimp recognises PLY by content, in any case, whatever the extension.
  const std::string glb = dir + "/ply_inside.glb";
  test::write_file(glb, "Ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n");
  expect_clean_failure("inspect " + glb, {glb, "no end_header"}, "PLY text in a .glb");
}

TEST(BadInput, NonManifoldAndNanGarments) {
  const std::string dir = test::temp_dir("bad_garments");
  // Three triangles on one edge.
  const std::string fan = dir + "/fan.obj";
  test::write_file(fan, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n");
  test::CommandResult r = test::run_pb4u("-q inspect " + fan);
  ASSERT_EQ(r.exit_code, 0) << r.err;  // inspect reports it ...
  EXPECT_NE(r.out.find("manifold: no"), std::string::npos) << r.out;
  // ... a simulation refuses it as a garment.
  expect_clean_failure("simulate --method reference --scene " + scene_file(dir, fan) + " --out " + dir + "/o",
                       fan, "non-manifold garment");
  const std::string nan_ply = dir + "/nan.ply";
  test::write_file(nan_ply,
                   "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                   "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n");
  expect_clean_failure("inspect " + nan_ply, nan_ply, "NaN PLY");
}

TEST(BadInput, BvhMotions) {
  const std::string dir = test::temp_dir("bad_bvh");
  for (const auto& b : broken_versions(dir, kBvh, ".bvh")) expect_clean_failure("inspect " + b.path, b.path, "BVH " + b.name);
  std::string text = read_bytes(kBvh);
  // A NaN channel value and a frame with too few values.
  const size_t motion = text.find("Frame Time:");
  ASSERT_NE(motion, std::string::npos);
  const size_t first_row = text.find('\n', motion) + 1;
  std::string nan_text = text;
  nan_text.replace(first_row, nan_text.find(' ', first_row) - first_row, "nan");
  test::write_file(dir + "/nan.bvh", nan_text);
  expect_clean_failure("inspect " + dir + "/nan.bvh", dir + "/nan.bvh", "BVH NaN value");
  test::write_file(dir + "/short.bvh", text.substr(0, text.find('\n', first_row)) + " \n1 2 3\n");
  expect_clean_failure("inspect " + dir + "/short.bvh", dir + "/short.bvh", "BVH short frame");
}

TEST(BadInput, YamlConfigsAndScenes) {
  const std::string dir = test::temp_dir("bad_yaml");
  const std::string train_cfg = kSource + "/configs/train/tiny.yaml";
  // An empty YAML file is a config of defaults, and most cuts of one are valid YAML: the
  // broken versions are a missing file, random bytes and a file cut inside a flow list.
  std::vector<Broken> files = broken_versions(dir, train_cfg, ".yaml");
  test::write_file(files[2].path, read_bytes(train_cfg) + "\nlevels: [1, 2\n");
  files.erase(files.begin() + 1);
  for (const auto& b : files)
    expect_clean_failure("simulate --method reference --scene " + b.path + " --out " + dir + "/sim", b.path,
                         "scene " + b.name);
  expect_clean_failure("train --config " + files[2].path + " --out " + dir + "/run", files[2].path, "train config");
  expect_clean_failure("generate --config " + files[2].path + " --out " + dir + "/gen", files[2].path, "data config");
  expect_clean_failure("evaluate --checkpoint " + kExport + " --config " + files[1].path, files[1].path, "eval config");
  // Unknown keys, wrong types and out-of-range values name the file and the key path.
  const std::string scene = scene_file(dir);
  test::write_file(dir + "/unknown.yaml", read_bytes(scene) + "garmnet: {}\n");
  expect_clean_failure("simulate --method reference --scene " + dir + "/unknown.yaml --out " + dir + "/s1", "garmnet",
                       "unknown key");
  test::write_file(dir + "/type.yaml", "frames: lots\n");
  expect_clean_failure("simulate --method reference --scene " + dir + "/type.yaml --out " + dir + "/s2",
                       {dir + "/type.yaml", "'frames'"}, "wrong type");
  test::write_file(dir + "/null_key.yaml", "? :\n");  // found by config_fuzz
  expect_clean_failure("simulate --method reference --scene " + dir + "/null_key.yaml --out " + dir + "/s0",
                       {dir + "/null_key.yaml", "plain name"}, "null key");
  test::write_file(dir + "/nested.yaml", read_bytes(scene) + "material: {mu: [1, 2]}\n");
  expect_clean_failure("simulate --method reference --scene " + dir + "/nested.yaml --out " + dir + "/s3",
                       "material.mu", "list for a number");
  expect_clean_failure("simulate --method reference --scene " + scene + " --set material.density=-1 --out " + dir + "/s4",
                       "material.density", "out of range via --set");
  expect_clean_failure("train --config " + train_cfg + " --set optim.lr=abc --out " + dir + "/r2", "optim.lr",
                       "wrong type via --set");
  EXPECT_FALSE(fs::exists(dir + "/r2"));
}

TEST(BadInput, HdfDatasets) {
  const std::string dir = test::temp_dir("bad_h5");
  std::vector<Broken> files = broken_versions(dir, test::tiny_dataset(), ".h5");
  for (const auto& b : files) expect_clean_failure("inspect " + b.path, b.path, "dataset " + b.name);
  expect_clean_failure("train --config " + kSource + "/configs/train/tiny.yaml --set data.dataset=" + files[2].path +
                           " --out " + dir + "/run",
                       files[2].path, "truncated training dataset");
  // An HDF5 file that is something else (an export) where a dataset is expected.
  expect_clean_failure("train --config " + kSource + "/configs/train/tiny.yaml --set data.dataset=" + kExport +
                           " --out " + dir + "/run_export",
                       kExport, "export as a dataset");
}

TEST(BadInput, CheckpointsAndExports) {
  const std::string dir = test::temp_dir("bad_ckpt");
  const std::string scene = scene_file(dir);
  const std::string ckpt = tiny_run() + "/final.pt";
  std::vector<Broken> files = broken_versions(dir, ckpt, ".pt");
  for (const auto& b : broken_versions(dir, kExport, ".h5"))
    if (b.name != "missing") files.push_back(b);
  for (const auto& b : files) expect_clean_failure("inspect " + b.path, b.path, "model file " + b.name);
  const std::string truncated_pt = files[2].path, truncated_export = files[5].path;  // the export cut in half
  for (const std::string& bad : {truncated_pt, truncated_export}) {
    expect_clean_failure("export --checkpoint " + bad + " --out " + dir + "/x.h5", bad, "export");
    expect_clean_failure("simulate --checkpoint " + bad + " --scene " + scene + " --out " + dir + "/sim", bad, "simulate");
  }
  expect_clean_failure("evaluate --checkpoint " + truncated_pt + " --config " + kSource +
                           "/configs/eval/tiny.yaml --set dataset=" + test::tiny_dataset(),
                       truncated_pt, "evaluate");
  EXPECT_FALSE(fs::exists(dir + "/x.h5"));
}

TEST(BadInput, CheckpointThatDoesNotMatchTheConfig) {
  // Resuming the run with a wider model: the newest checkpoint no longer fits.
  const std::string run = test::temp_dir("badinput_resume") + "/run";
  fs::copy(tiny_run(), run, fs::copy_options::recursive);
  const std::string base = "train --config " + kSource + "/configs/train/tiny.yaml --set data.dataset=" +
                           test::tiny_dataset() + " --set run.steps=2 --out " + run + " --resume";
  const std::string metrics_before = read_bytes(run + "/metrics.jsonl");
  expect_clean_failure(base + " --set model.latent=24", "checkpoints/", "resume with another model config");
  EXPECT_EQ(read_bytes(run + "/metrics.jsonl"), metrics_before);
}

// Runs `body` on a directory made immutable (chattr +i, which binds root too), always undone.
void with_read_only_dir(const std::string& dir, const std::function<void()>& body) {
  if (std::system(("chattr +i '" + dir + "' 2>/dev/null").c_str()) != 0)
    GTEST_SKIP() << "chattr +i is not available here (needed to make a directory read-only for root)";
  struct Undo {
    std::string dir;
    ~Undo() { [[maybe_unused]] int rc = std::system(("chattr -i '" + dir + "'").c_str()); }
  } undo{dir};
  body();
}

TEST(BadInput, OutputsThatCannotBeWrittenAndNothingOverwritten) {
  const std::string dir = test::temp_dir("bad_out");
  const std::string scene = scene_file(dir);
  const std::string a_file = dir + "/a_file";
  test::write_file(a_file, "precious\n");
  expect_clean_failure("simulate --method reference --scene " + scene + " --out " + a_file, a_file, "simulate into a file");
  expect_clean_failure("generate --config " + kSource + "/configs/data/tiny.yaml --out " + a_file, a_file,
                       "generate into a file");
  expect_clean_failure("train --config " + kSource + "/configs/train/tiny.yaml --set data.dataset=" +
                           test::tiny_dataset() + " --out " + a_file,
                       a_file, "train into a file");
  expect_clean_failure("export --checkpoint " + kExport + " --out " + a_file + "/model.h5", a_file,
                       "export under a file");
  EXPECT_EQ(read_bytes(a_file), "precious\n");

  // A failing command leaves an existing output untouched.
  const std::string existing = dir + "/model.h5";
  test::write_file(existing, "previous export\n");
  test::write_file(dir + "/bad.pt", "not a checkpoint");
  expect_clean_failure("export --checkpoint " + dir + "/bad.pt --out " + existing, dir + "/bad.pt", "bad export source");
  EXPECT_EQ(read_bytes(existing), "previous export\n");

  const std::string ro = dir + "/read_only";
  fs::create_directories(ro);
  test::write_file(ro + "/garment.pc2", "old cache\n");
  with_read_only_dir(ro, [&] {
    expect_clean_failure("simulate --method reference --scene " + scene + " --out " + ro, ro, "read-only simulate dir");
    expect_clean_failure("export --checkpoint " + kExport + " --out " + ro + "/model.h5", ro, "read-only export dir");
    expect_clean_failure("train --config " + kSource + "/configs/train/tiny.yaml --set data.dataset=" +
                             test::tiny_dataset() + " --out " + ro + "/run",
                         ro, "read-only run parent");
  });
  EXPECT_EQ(read_bytes(ro + "/garment.pc2"), "old cache\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(ro), fs::directory_iterator()), 1);
}

}  // namespace
}  // namespace pb4u

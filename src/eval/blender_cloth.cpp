#include "pb4u/eval/blender_cloth.h"

#include <spdlog/spdlog.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "pb4u/rollout/rollout.h"
#include "pb4u/io/mesh_io.h"
#include "pb4u/io/point_cache.h"
#include "pb4u/util/error.h"
#include "pb4u/util/resource_dir.h"
#include "pb4u/util/subprocess.h"

namespace pb4u {
namespace fs = std::filesystem;

namespace {

std::string tail_of(const std::string& path, int lines) {
  std::ifstream in(path);
  std::vector<std::string> all;
  for (std::string l; std::getline(in, l);) all.push_back(l);
  std::string out;
  for (size_t i = all.size() > size_t(lines) ? all.size() - lines : 0; i < all.size(); ++i) out += all[i] + " | ";
  return out;
}

}  // namespace

std::string find_blender(const std::string& executable) {
  std::error_code ec;
  if (executable.find('/') != std::string::npos) return fs::exists(executable, ec) ? executable : "";
  const std::vector<std::string> found = find_all_on_path(executable);
  return found.empty() ? "" : found.front();
}

BlenderRollout run_blender_cloth(const RolloutInput& in, const std::string& blender, int quality, int threads,
                                 double collision_distance, const std::string& work_dir) {
  std::error_code ec;
  fs::create_directories(work_dir, ec);
  if (ec) fail_file(work_dir, "cannot create: " + ec.message());
  const std::string dir = work_dir + "/";
  write_obj(dir + "garment_rest.obj", TriMesh{in.garment_rest.V, in.garment_rest.F});
  write_obj(dir + "garment_0000.obj", TriMesh{in.x0, in.garment_rest.F});
  const std::string script = resource_path("scripts/blender_cloth.py");
  if (script.empty())
    throw Error("scripts/blender_cloth.py: not found beside the pb4u binary (set PB4U_DATA_DIR)");
  const Material& m = in.material;
  // Numbers as an ostream prints them (6 significant digits), as they always went to Blender.
  auto text = [](double v) {
    std::ostringstream s;
    s << v;
    return s.str();
  };
  std::vector<std::string> argv{blender, "-b", "--factory-startup", "-t", std::to_string(threads), "-P", script,
                                "--", "--start", dir + "garment_0000.obj", "--rest", dir + "garment_rest.obj",
                                "--frames", std::to_string(in.steps), "--out", dir + "blender.pc2",
                                "--times", dir + "times.csv", "--quality", std::to_string(quality),
                                "--collision-distance", text(collision_distance), "--fps", text(1.0 / in.dt),
                                "--density", text(m.density), "--mu", text(m.mu), "--lambda", text(m.lambda),
                                "--thickness", text(m.thickness), "--bending", text(m.bending)};
  if (!in.body.empty() && in.effects.needs_body()) {
    write_obj(dir + "body_0000.obj", TriMesh{in.body[0], in.body_faces});
    std::vector<Eigen::MatrixXd> body(in.body.begin(), in.body.begin() + std::min<size_t>(in.body.size(), in.steps + 1));
    write_pc2(dir + "body.pc2", body);
    argv.insert(argv.end(), {"--body", dir + "body_0000.obj", "--body-cache", dir + "body.pc2"});
  }
  if (in.effects.pins && !in.pinned.empty()) {
    std::ofstream pins(dir + "pins.txt");
    for (int i : in.pinned) pins << i << '\n';
    argv.insert(argv.end(), {"--pins", dir + "pins.txt"});
  }
  const std::string log = dir + "blender.log";
  std::string shown;
  for (const auto& a : argv) shown += (shown.empty() ? "" : " ") + a;
  spdlog::debug("blender: {}", shown);
  if (run_process(argv, log) != 0 || !fs::exists(dir + "blender.pc2"))
    fail_file(log, "Blender's cloth run failed: " + tail_of(log, 4));
  BlenderRollout out;
  out.frames = read_pc2(dir + "blender.pc2");
  if (int(out.frames.size()) != in.steps + 1 || out.frames[0].rows() != in.x0.rows())
    fail_file(dir + "blender.pc2", "expected " + std::to_string(in.steps + 1) + " frames of " +
                                       std::to_string(in.x0.rows()) + " vertices");
  std::ifstream times(dir + "times.csv");
  std::string line;
  std::getline(times, line);  // header
  for (int frame = 0; std::getline(times, line); ++frame)
    if (frame > 0) out.frame_ms.push_back(std::stod(line.substr(line.find(',') + 1)));
  return out;
}

}  // namespace pb4u

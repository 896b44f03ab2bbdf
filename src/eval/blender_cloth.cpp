#include "pb4u/eval/blender_cloth.h"

#include <spdlog/spdlog.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "pb4u/eval/rollout.h"
#include "pb4u/io/mesh_io.h"
#include "pb4u/sim/point_cache.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace fs = std::filesystem;

namespace {

std::string quoted(const std::string& s) { return "'" + s + "'"; }

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
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    const fs::path candidate = fs::path(dir.empty() ? "." : dir) / executable;
    if (fs::exists(candidate, ec) && !fs::is_directory(candidate, ec)) return candidate.string();
  }
  return "";
}

BlenderRollout run_blender_cloth(const RolloutInput& in, const std::string& blender, int quality, int threads,
                                 double collision_distance, const std::string& work_dir) {
  std::error_code ec;
  fs::create_directories(work_dir, ec);
  if (ec) fail_file(work_dir, "cannot create: " + ec.message());
  const std::string dir = work_dir + "/";
  write_obj(dir + "garment_rest.obj", TriMesh{in.garment_rest.V, in.garment_rest.F});
  write_obj(dir + "garment_0000.obj", TriMesh{in.x0, in.garment_rest.F});
  const Material& m = in.material;
  std::ostringstream cmd;
  cmd << quoted(blender) << " -b --factory-startup -t " << threads << " -P "
      << quoted(std::string(PB4U_SOURCE_DIR) + "/scripts/blender_cloth.py")
      << " -- --start " << quoted(dir + "garment_0000.obj") << " --rest " << quoted(dir + "garment_rest.obj")
      << " --frames " << in.steps << " --out " << quoted(dir + "blender.pc2") << " --times "
      << quoted(dir + "times.csv") << " --quality " << quality << " --collision-distance " << collision_distance
      << " --fps " << 1.0 / in.dt << " --density " << m.density << " --mu " << m.mu << " --lambda " << m.lambda
      << " --thickness " << m.thickness << " --bending " << m.bending;
  if (!in.body.empty() && in.effects.needs_body()) {
    write_obj(dir + "body_0000.obj", TriMesh{in.body[0], in.body_faces});
    std::vector<Eigen::MatrixXd> body(in.body.begin(), in.body.begin() + std::min<size_t>(in.body.size(), in.steps + 1));
    write_pc2(dir + "body.pc2", body);
    cmd << " --body " << quoted(dir + "body_0000.obj") << " --body-cache " << quoted(dir + "body.pc2");
  }
  if (in.effects.pins && !in.pinned.empty()) {
    std::ofstream pins(dir + "pins.txt");
    for (int i : in.pinned) pins << i << '\n';
    cmd << " --pins " << quoted(dir + "pins.txt");
  }
  const std::string log = dir + "blender.log";
  cmd << " > " << quoted(log) << " 2>&1";
  spdlog::debug("blender: {}", cmd.str());
  if (std::system(cmd.str().c_str()) != 0 || !fs::exists(dir + "blender.pc2"))
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

#include "pb4u/data/generate.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <filesystem>
#include <random>
#include <set>

#include "pb4u/body/bvh.h"
#include "pb4u/garment/import_garment.h"
#include "pb4u/garment/skin_weight_transfer.h"
#include "pb4u/util/error.h"
#include "pb4u/util/progress.h"

namespace pb4u {
namespace fs = std::filesystem;

namespace {

std::string resolve(const std::string& path, const std::string& base_dir) {
  if (fs::exists(path) || fs::path(path).is_absolute() || base_dir.empty()) return path;
  fs::path alt = fs::path(base_dir) / path;
  return fs::exists(alt) ? alt.string() : path;
}

bool contains(const std::vector<std::string>& v, const std::string& x) {
  return std::find(v.begin(), v.end(), x) != v.end();
}

}  // namespace

void validate_generate_config(const GenerateConfig& c, const std::string& where) {
  validate_levels(c.levels, where);
  std::set<std::string> names;
  for (size_t i = 0; i < c.bodies.size(); ++i) {
    const std::string key = where + ": bodies[" + std::to_string(i) + "]";
    if (c.bodies[i].name.empty() || c.bodies[i].name.find('/') != std::string::npos)
      throw Error(key + ".name: must be non-empty without '/'");
    if (!names.insert(c.bodies[i].name).second) throw Error(key + ".name: duplicate body name");
  }
  for (size_t i = 0; i < c.templates.size(); ++i)
    if (!contains(garment_template_names(), c.templates[i]))
      throw Error(where + ": templates[" + std::to_string(i) + "]: unknown template '" +
                  c.templates[i] + "' (tshirt, tank_top, long_sleeve, long_dress, skirt)");
  for (size_t i = 0; i < c.procedural.kinds.size(); ++i)
    if (!contains(procedural_motion_names(), c.procedural.kinds[i]))
      throw Error(where + ": procedural.kinds[" + std::to_string(i) + "]: unknown motion '" +
                  c.procedural.kinds[i] + "' (walk, run, jump, arm_raise, torso_twist, spin)");
  if (c.procedural.per_kind > 0 && !c.procedural.kinds.empty() && !names.count(c.procedural.body))
    throw Error(where + ": procedural.body: no body named '" + c.procedural.body + "'");
  if (!c.bvh.files.empty() && !names.count(c.bvh.body))
    throw Error(where + ": bvh.body: no body named '" + c.bvh.body + "'");
  for (const auto* range : {&c.procedural.ranges.speed, &c.procedural.ranges.amplitude})
    if (range->size() != 2 || !((*range)[0] > 0 && (*range)[0] <= (*range)[1]))
      throw Error(where + ": procedural.ranges: speed and amplitude must be [min, max] with 0 < min <= max");
}

Dataset generate_dataset(const GenerateConfig& c, const std::string& base_dir) {
  Dataset data;
  data.level_triangles = c.levels.triangles;
  data.density = c.density;
  const int L = static_cast<int>(c.levels.triangles.size());
  const int garments_per_body = static_cast<int>(c.templates.size() + c.garment_files.size());
  const int motions = static_cast<int>(c.procedural.kinds.size()) * c.procedural.per_kind +
                      static_cast<int>(c.bvh.files.size());
  Progress progress("generate", static_cast<int64_t>(c.bodies.size()) * (1 + garments_per_body * L) + motions,
                    "items");

  for (const BodySpec& spec : c.bodies) {
    Skeleton skeleton = spec.skeleton == "builtin"
                            ? builtin_skeleton()
                            : read_bvh(resolve(spec.skeleton, base_dir), 0.0, c.bvh.scale).skeleton;
    BodyRecord rec;
    rec.body = build_mannequin(spec.name, skeleton, c.mannequin);
    progress.step(1, "body " + spec.name);
    spdlog::debug("body {}: {} vertices", spec.name, rec.body.mesh.num_vertices());
    for (const std::string& name : c.templates) {
      const TriMesh surface = garment_template_surface(name, rec.body, c.mannequin, c.garments);
      GarmentLevels gl;
      gl.name = name;
      for (int k = 0; k < L; ++k) {
        gl.levels.push_back(make_garment(name, surface, rec.body, c.levels.triangles[k]));
        progress.step(1, spec.name + "/" + name + " level " + std::to_string(k + 1));
      }
      rec.garments.push_back(std::move(gl));
    }
    for (const std::string& file : c.garment_files) {
      GarmentLevels gl;
      gl.name = fs::path(file).stem().string();
      for (int k = 0; k < L; ++k) {
        Garment g;
        g.name = gl.name;
        g.mesh = import_garment(resolve(file, base_dir), c.levels.triangles[k]);
        g.weights = transfer_skin_weights(g.mesh.V, rec.body);
        gl.levels.push_back(std::move(g));
        progress.step(1, spec.name + "/" + gl.name + " level " + std::to_string(k + 1));
      }
      rec.garments.push_back(std::move(gl));
    }
    data.bodies.push_back(std::move(rec));
  }

  std::mt19937 rng(static_cast<unsigned>(c.seed));
  if (c.procedural.per_kind > 0) {
    const BodyRecord* body = data.find_body(c.procedural.body);
    for (const std::string& kind : c.procedural.kinds)
      for (int i = 0; i < c.procedural.per_kind; ++i) {
        MotionParams p = random_motion_params(kind, c.procedural.frames, c.procedural.ranges, rng);
        p.fps = c.fps;
        MotionRecord m;
        m.name = kind + "_" + std::to_string(i + 1);
        m.body = body->body.name;
        m.source = "procedural:" + kind;
        m.motion = procedural_motion(body->body.skeleton, body->body.bind, p);
        data.motions.push_back(std::move(m));
        progress.step(1, "motion " + kind);
      }
  }
  for (const std::string& file : c.bvh.files) {
    const std::string path = resolve(file, base_dir);
    BvhFile bvh = read_bvh(path, c.fps, c.bvh.scale);
    const BodyRecord* body = data.find_body(c.bvh.body);
    if (bvh.skeleton.names != body->body.skeleton.names)
      fail_file(path, "its joints differ from body '" + c.bvh.body + "' (build that body from this file's skeleton)");
    if (c.bvh.max_frames > 0 && bvh.motion.num_frames() > c.bvh.max_frames)
      bvh.motion.frames.resize(c.bvh.max_frames);
    MotionRecord m;
    m.name = fs::path(file).stem().string();
    m.body = c.bvh.body;
    m.source = file;
    m.motion = std::move(bvh.motion);
    progress.step(1, "motion " + m.name);
    data.motions.push_back(std::move(m));
  }
  // Split: a seeded shuffle, the first test_fraction of motions held out for testing.
  std::vector<size_t> order(data.motions.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::shuffle(order.begin(), order.end(), rng);
  size_t tests = static_cast<size_t>(std::round(c.test_fraction * order.size()));
  if (c.test_fraction > 0 && tests == 0) tests = 1;
  if (order.size() < 2) tests = 0;
  tests = std::min(tests, order.size() - (order.empty() ? 0 : 1));  // keep one for training
  for (size_t i = 0; i < order.size(); ++i) data.motions[order[i]].split = i < tests ? "test" : "train";
  progress.finish();
  data.config_yaml = config_to_yaml(c);
  return data;
}

}  // namespace pb4u

#include "pb4u/data/generate.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <filesystem>
#include <random>
#include <set>

#include "pb4u/body/bvh.h"
#include "pb4u/body/skinned_mesh_import.h"
#include "pb4u/garment/clear_of_body.h"
#include "pb4u/garment/import_garment.h"
#include "pb4u/garment/skin_weight_transfer.h"
#include "pb4u/mesh/remesh.h"
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

// One level of a garment: its rest mesh cleared of the body at the bind pose
// (garment/clear_of_body.h), then skinned to it.
Garment garment_level(const std::string& name, TriMesh mesh, const Body& body, const GarmentTemplateConfig& c,
                      const std::string& label) {
  Garment g;
  g.name = name;
  g.mesh = std::move(mesh);
  if (c.rest_clearance > 0) clear_of_body_logged(g.mesh, body.mesh, c.rest_clearance, label);
  g.weights = garment_skin_weights(g.mesh, body, c.skin_weight_options());
  return g;
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
  for (const auto* range : {&c.procedural.ranges.speed, &c.procedural.ranges.amplitude,
                            &c.procedural.heldout_ranges.speed, &c.procedural.heldout_ranges.amplitude})
    if (range->size() != 2 || !((*range)[0] > 0 && (*range)[0] <= (*range)[1]))
      throw Error(where + ": procedural.ranges: speed and amplitude must be [min, max] with 0 < min <= max");
}

Dataset generate_dataset(const GenerateConfig& c, const std::string& base_dir, int workers) {
  if (workers <= 0) workers = std::max(1u, std::thread::hardware_concurrency());
  Dataset data;
  data.level_triangles = c.levels.triangles;
  data.density = c.density;
  const int L = static_cast<int>(c.levels.triangles.size());
  int64_t items = static_cast<int64_t>(c.procedural.kinds.size()) *
                      (c.procedural.per_kind + c.procedural.heldout_per_kind) +
                  static_cast<int64_t>(c.bvh.files.size() + c.bvh.heldout_files.size());
  for (const BodySpec& spec : c.bodies)
    items += 1 + static_cast<int64_t>((spec.mesh.empty() ? c.templates.size() : 0) + c.garment_files.size()) * L;
  Progress progress("generate", items, "items");

  std::vector<MotionRecord> file_motions;  // animations of skinned mesh bodies
  for (const BodySpec& spec : c.bodies) {
    BodyRecord rec;
    const bool mannequin = spec.mesh.empty();
    if (mannequin) {
      Skeleton skeleton = spec.skeleton == "builtin"
                              ? builtin_skeleton()
                              : read_bvh(resolve(spec.skeleton, base_dir), 0.0, c.bvh.scale).skeleton;
      rec.body = build_mannequin(spec.name, skeleton, c.mannequin);
    } else {
      SkinnedMeshFile file = read_skinned_mesh(resolve(spec.mesh, base_dir), c.fps);
      rec.body = std::move(file.body);
      rec.body.name = spec.name;
      for (size_t a = 0; a < file.motions.size(); ++a) {
        MotionRecord m;
        m.name = spec.name + "_" + file.animation_names[a];
        m.body = spec.name;
        m.source = spec.mesh;
        m.motion = std::move(file.motions[a]);
        file_motions.push_back(std::move(m));
      }
    }
    progress.step(1, "body " + spec.name);
    spdlog::debug("body {}: {} vertices", spec.name, rec.body.mesh.num_vertices());
    // Garments are independent: one job each, spread over `workers` threads.
    const int templates = mannequin ? static_cast<int>(c.templates.size()) : 0;
    const int jobs = templates + static_cast<int>(c.garment_files.size());
    rec.garments.resize(jobs);
    std::vector<std::exception_ptr> errors(jobs);
    std::atomic<int> next{0};
    std::mutex progress_mutex;
    auto run_job = [&](int job) {
      GarmentLevels& gl = rec.garments[job];
      const bool is_template = job < templates;
      TriMesh surface;
      std::string file;
      if (is_template) {
        gl.name = c.templates[job];
        surface = remesh_source_for(
            garment_template_surface(gl.name, rec.body, c.mannequin, c.garments),
            *std::max_element(c.levels.triangles.begin(), c.levels.triangles.end()));
      } else {
        file = resolve(c.garment_files[job - templates], base_dir);
        gl.name = fs::path(file).stem().string();
        // A file named like a template (tshirt.obj) must not be confused with it.
        if (contains(c.templates, gl.name)) gl.name += "_file";
      }
      for (int k = 0; k < L; ++k) {
        const int triangles = c.levels.triangles[k];
        gl.levels.push_back(garment_level(
            gl.name, is_template ? remesh_to_triangle_count(surface, triangles) : import_garment(file, triangles),
            rec.body, c.garments, spec.name + "/" + gl.name + " level " + std::to_string(k + 1)));
        std::lock_guard<std::mutex> lock(progress_mutex);
        progress.step(1, spec.name + "/" + gl.name + " level " + std::to_string(k + 1));
      }
    };
    auto worker = [&] {
      for (int job; (job = next++) < jobs;) {
        try {
          run_job(job);
        } catch (...) {
          errors[job] = std::current_exception();
        }
      }
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < std::min(workers, jobs); ++t) pool.emplace_back(worker);
    worker();
    for (auto& t : pool) t.join();
    for (auto& e : errors)
      if (e) std::rethrow_exception(e);
    data.bodies.push_back(std::move(rec));
  }

  for (auto& m : file_motions) data.motions.push_back(std::move(m));
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
  auto add_bvh = [&](const std::string& file, bool heldout) {
    const std::string path = resolve(file, base_dir);
    BvhFile bvh = read_bvh(path, c.fps, c.bvh.scale);
    const BodyRecord* body = data.find_body(c.bvh.body);
    if (bvh.skeleton.names != body->body.skeleton.names)
      fail_file(path, "its joints differ from body '" + c.bvh.body + "' (build that body from this file's skeleton)");
    // Held-out files are kept whole: they are the long (10 s) stability rollouts.
    if (!heldout && c.bvh.max_frames > 0 && bvh.motion.num_frames() > c.bvh.max_frames)
      bvh.motion.frames.resize(c.bvh.max_frames);
    MotionRecord m;
    m.name = fs::path(file).stem().string();
    m.body = c.bvh.body;
    m.source = file;
    m.motion = std::move(bvh.motion);
    if (heldout) m.split = "heldout";
    progress.step(1, "motion " + m.name);
    data.motions.push_back(std::move(m));
  };
  for (const std::string& file : c.bvh.files) add_bvh(file, false);
  for (const std::string& file : c.bvh.heldout_files) add_bvh(file, true);
  // Held-out procedural motions: parameters outside the training ranges, their own RNG so
  // that adding them leaves every other motion and the split unchanged.
  if (c.procedural.heldout_per_kind > 0) {
    std::mt19937 heldout_rng(static_cast<unsigned>(c.seed) + 7919u);
    const BodyRecord* body = data.find_body(c.procedural.body);
    for (const std::string& kind : c.procedural.kinds)
      for (int i = 0; i < c.procedural.heldout_per_kind; ++i) {
        MotionParams p = random_motion_params(kind, c.procedural.heldout_frames, c.procedural.heldout_ranges,
                                              heldout_rng);
        p.fps = c.fps;
        MotionRecord m;
        m.name = kind + "_heldout_" + std::to_string(i + 1);
        m.body = body->body.name;
        m.source = "procedural:" + kind;
        m.split = "heldout";
        m.motion = procedural_motion(body->body.skeleton, body->body.bind, p);
        progress.step(1, "motion " + m.name);
        data.motions.push_back(std::move(m));
      }
  }
  // Split: a seeded shuffle of the other motions, the first test_fraction of them for testing.
  std::vector<size_t> order;
  for (size_t i = 0; i < data.motions.size(); ++i)
    if (data.motions[i].split != "heldout") order.push_back(i);
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

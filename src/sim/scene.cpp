#include "pb4u/sim/scene.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "pb4u/body/bvh.h"
#include "pb4u/body/procedural_motion.h"
#include "pb4u/data/dataset.h"
#include "pb4u/data/lbs_frame.h"
#include "pb4u/rollout/rollout.h"
#include "pb4u/rollout/settled_start.h"
#include "pb4u/garment/clear_of_body.h"
#include "pb4u/garment/garment_template.h"
#include "pb4u/garment/import_garment.h"
#include "pb4u/garment/skin_weight_transfer.h"
#include "pb4u/io/frame_sequence.h"
#include "pb4u/io/mesh_io.h"
#include "pb4u/mesh/topology.h"
#include "pb4u/scene/pins.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace fs = std::filesystem;

namespace {

// A file, or a numbered pattern (body_%04d.obj) whose frame 0 or 1 is there.
bool file_or_first_frame_exists(const fs::path& path) {
  const std::string p = path.string();
  if (p.find('%') == std::string::npos) return fs::exists(path);
  char name[4096];
  for (int frame : {0, 1}) {
    std::snprintf(name, sizeof name, p.c_str(), frame);
    if (fs::exists(name)) return true;
  }
  return false;
}

std::string resolve(const std::string& path, const std::string& scene_path) {
  if (path.empty() || file_or_first_frame_exists(path) || fs::path(path).is_absolute()) return path;
  fs::path alt = fs::path(scene_path).parent_path() / path;
  return file_or_first_frame_exists(alt) ? alt.string() : path;
}

const GarmentLevels* find_garment(const BodyRecord& body, const std::string& name) {
  for (const auto& g : body.garments)
    if (g.name == name) return &g;
  return nullptr;
}

Motion scene_motion(const SceneBody& sb, const Dataset& data, const Body& body, int frames,
                    const std::string& where) {
  const std::string procedural = "procedural:";
  Motion motion;
  if (sb.motion.rfind(procedural, 0) == 0) {
    MotionParams p;
    p.kind = sb.motion.substr(procedural.size());
    p.speed = sb.speed;
    p.amplitude = sb.amplitude;
    p.frames = frames + 1;
    motion = procedural_motion(body.skeleton, body.bind, p);
  } else if (fs::path(sb.motion).extension() == ".bvh") {
    const std::string path = resolve(sb.motion, where);
    BvhFile bvh = read_bvh(path, 30.0, sb.bvh_scale);
    if (bvh.skeleton.names != body.skeleton.names)
      fail_file(path, "its joints differ from body '" + body.name + "'");
    motion = std::move(bvh.motion);
  } else {
    for (const auto& m : data.motions)
      if (m.name == sb.motion && m.body == body.name) motion = m.motion;
    if (motion.frames.empty())
      throw Error(where + ": body.motion: no motion '" + sb.motion + "' for body '" + body.name +
                  "' in the dataset (or use procedural:<kind> or a .bvh file)");
  }
  if (motion.frames.empty()) throw Error(where + ": body.motion: the motion has no frames");
  return motion;
}

}  // namespace

TriMesh square_cloth(double size, int res, double height) {
  TriMesh m;
  m.V.resize(res * res, 3);
  const double h = size / (res - 1);
  for (int r = 0; r < res; ++r)
    for (int c = 0; c < res; ++c) m.V.row(r * res + c) << -size / 2 + c * h, height - r * h, 0.0;
  m.F.resize(2 * (res - 1) * (res - 1), 3);
  int f = 0;
  for (int r = 0; r + 1 < res; ++r)
    for (int c = 0; c + 1 < res; ++c) {
      const int a = r * res + c, b = a + 1, d = a + res, e = d + 1;
      if ((r + c) % 2 == 0) {
        m.F.row(f++) << a, d, b;
        m.F.row(f++) << b, d, e;
      } else {
        m.F.row(f++) << a, d, e;
        m.F.row(f++) << a, e, b;
      }
    }
  return m;
}

SceneSetup build_scene(const SceneConfig& scene, const std::string& where) {
  SceneSetup s;
  s.effects = Effects::from_names(scene.effects, where + ": effects");
  // A body: a dataset's, skinned and moved by a motion, or a mesh sequence (body.mesh_sequence).
  const bool skeleton_body = !scene.body.dataset.empty(), sequence_body = !scene.body.mesh_sequence.empty();
  const bool has_body = skeleton_body || sequence_body;
  if (skeleton_body && sequence_body)
    throw Error(where + ": body: give body.dataset or body.mesh_sequence, not both");
  if (s.effects.needs_body() && !has_body)
    throw Error(where + ": effects: collision/friction need a body, and body.dataset is empty");

  Dataset data;
  const BodyRecord* record = nullptr;
  const bool need_dataset = skeleton_body || scene.garment.source == "template";
  if (need_dataset) {
    const std::string path = resolve(skeleton_body ? scene.body.dataset : scene.garment.dataset, where);
    if (path.empty()) throw Error(where + ": garment.dataset: a template garment needs a generated dataset");
    data = read_dataset(path);
    record = data.find_body(scene.body.name);
    if (!record) throw Error(where + ": body.name: no body '" + scene.body.name + "' in " + path);
  }

  Garment garment;
  const SceneGarment& g = scene.garment;
  if (g.source == "template") {
    const GarmentLevels* levels = find_garment(*record, g.name);
    if (!levels) throw Error(where + ": garment.name: no garment '" + g.name + "' on body '" + record->body.name + "'");
    if (g.level > int(levels->levels.size()))
      throw Error(where + ": garment.level: " + std::to_string(g.level) + " but the dataset has " +
                  std::to_string(levels->levels.size()) + " levels");
    garment = levels->levels[g.level - 1];
  } else if (g.source == "file") {
    if (g.file.empty()) throw Error(where + ": garment.file: required for source file");
    const std::string path = resolve(g.file, where);
    garment.name = fs::path(path).stem().string();
    if (g.keep_vertex_order && g.triangles > 0)
      throw Error(where + ": garment.keep_vertex_order: a remeshed garment (garment.triangles > 0) has new vertices");
    garment.mesh = g.keep_vertex_order ? read_mesh_in_file_order(path)
                   : g.triangles > 0   ? import_garment(path, g.triangles)
                                       : read_mesh(path);
    if (g.keep_vertex_order) {  // read as listed: a loose vertex would be cloth without mass
      std::vector<char> on_face(garment.mesh.V.rows(), 0);
      for (Eigen::Index i = 0; i < garment.mesh.F.size(); ++i) on_face[garment.mesh.F.data()[i]] = 1;
      const auto loose = std::find(on_face.begin(), on_face.end(), 0);
      if (loose != on_face.end())
        fail_file(path, "vertex " + std::to_string(loose - on_face.begin()) +
                            " is on no face; delete the loose vertices (garment.keep_vertex_order keeps every vertex)");
    }
    // Bending needs two faces per interior edge, the network a fan per vertex.
    const ManifoldReport manifold = check_manifold(garment.mesh.F, garment.mesh.num_vertices());
    if (!manifold.manifold())
      fail_file(path, "the garment is not manifold (" + std::to_string(manifold.nonmanifold_edges) +
                          " edges with more than two faces, " + std::to_string(manifold.nonmanifold_vertices) +
                          " non-manifold vertices); repair it first");
    if (skeleton_body) {
      // Around the body's bind pose, as a dataset's garments: its rest mesh cleared of the body first.
      const GarmentTemplateConfig fit;
      clear_of_body_logged(garment.mesh, record->body.mesh, fit.rest_clearance, path);
      garment.weights = garment_skin_weights(garment.mesh, record->body, fit.skin_weight_options());
    }
  } else {
    garment.name = "square";
    garment.mesh = square_cloth(g.size, g.resolution, g.height);
  }
  s.garment = garment.mesh;
  s.x0 = s.x_prev = garment.mesh.V;

  const bool skinned = skeleton_body && garment.weights.rows() == garment.mesh.V.rows();
  // Pins riding on the body: asked for, or a garment held at the waist (scene/waistband.h).
  const bool waistband = skinned && scene.waistband.holds(garment.name);
  if (skeleton_body && scene.pins.on_body && !skinned)
    throw Error(where + ": pins.on_body: the garment has no skinning weights to follow the body with");
  Motion motion;
  if (skeleton_body) {
    const Body& body = record->body;
    motion = scene_motion(scene.body, data, body, scene.frames, where);
    if (skinned) {
      LbsFrame f0 = lbs_frame(body, garment, motion, 0, scene.body.push_out_gap);
      s.x0 = f0.garment;
      s.x_prev = f0.garment_prev;
    }
    s.body_faces = body.mesh.F;
    // A motion shorter than the scene holds its last pose.
    for (int t = 0; t <= scene.frames; ++t)
      s.body.push_back(pose_body(body, motion.frames[std::min(t, motion.num_frames() - 1)]));
    if (waistband || (scene.pins.on_body && s.effects.pins))
      s.pin_targets = skinned_pin_targets(body, garment, motion, 0, s.body, scene.body.push_out_gap);
  } else if (sequence_body) {
    const std::string path = resolve(scene.body.mesh_sequence, where);
    FrameSequence seq = read_frame_sequence(path, "body");
    if (seq.faces.rows() == 0)
      fail_file(path, "body.mesh_sequence: a point cache has no faces; give numbered OBJ/PLY meshes or a .usda");
    s.body_faces = seq.faces;
    for (int t = 0; t <= scene.frames; ++t) s.body.push_back(seq.frames[std::min<size_t>(t, seq.frames.size() - 1)]);
    if (scene.pins.on_body && s.effects.pins) s.pin_targets = nearest_body_vertex_pin_targets(s.x0, s.body);
  }

  if (scene.pins.top_band > 0) s.pinned = top_band_vertices(s.x0, scene.pins.top_band);
  for (int i : scene.pins.vertices) {
    if (i < 0 || i >= s.x0.rows())
      throw Error(where + ": pins.vertices: " + std::to_string(i) + " is not a vertex (the garment has " +
                  std::to_string(s.x0.rows()) + ")");
    s.pinned.push_back(i);
  }
  if (s.effects.pins && s.pinned.empty())
    throw Error(where + ": pins: effect 'pins' is on but no vertex is pinned (set pins.top_band or pins.vertices)");
  if (!s.effects.pins) s.pinned.clear();
  if (waistband) {
    s.effects.pins = true;
    for (int i : top_band_vertices(garment.mesh.V, scene.waistband.band)) s.pinned.push_back(i);
    std::sort(s.pinned.begin(), s.pinned.end());
    s.pinned.erase(std::unique(s.pinned.begin(), s.pinned.end()), s.pinned.end());
  }
  if (!s.pin_targets.empty()) {
    const int through = hold_pins_free_of_body(s.garment.F, s.pinned, s.body, s.body_faces, &s.pin_targets, &s.x0, &s.x_prev);
    if (through > 0)
      spdlog::warn("{}: {} edges between pinned vertices still cut the body on a frame (pins are not moved further)",
                   where, through);
  }
  if (scene.body.start == "settled") {
    if (!skinned) throw Error(where + ": body.start: settled needs a skinned garment on a dataset's body (body.dataset)");
    const std::vector<int> riding = s.pin_targets.empty() ? std::vector<int>() : s.pinned;
    const Pose& next = motion.frames[size_t(std::min(1, motion.num_frames() - 1))];
    const SettledStart st = settled_start(record->body, garment, motion.frames[0], next, scene.body.settle_steps,
                                          scene.material, riding, scene.body.push_out_gap, scene.physics);
    settled_rollout_start(st, riding, riding.empty() ? st.x : s.pin_targets[0], &s.x0, &s.x_prev);
    spdlog::info("{}: {}", where, describe_settled_start(st, scene.body.settle_steps));
  }
  return s;
}

}  // namespace pb4u

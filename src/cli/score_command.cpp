// `pb4u score --frames SEQ [--garment REST] [--body-frames SEQ --body MESH] [--scene S]`: the
// SPEC 3 terms of a cloth sequence from any tool.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <iostream>

#include "pb4u/cli/commands.h"
#include "pb4u/eval/score.h"
#include "pb4u/io/frame_sequence.h"
#include "pb4u/io/mesh_io.h"
#include "pb4u/sim/scene.h"
#include "pb4u/util/atomic_file.h"
#include "pb4u/util/error.h"

namespace pb4u {

namespace {

struct ScoreArgs {
  std::string frames, garment, previous, body_frames, body, scene, config, format = "table", out;
  std::vector<std::string> sets;
};

// The sequence, its rest mesh and its body, from the files and (where they are silent) the scene.
ScoreInput score_input(const ScoreArgs& a) {
  ScoreInput in;
  FrameSequence garment = read_frame_sequence(a.frames, "garment");
  in.frames = std::move(garment.frames);
  const int T = static_cast<int>(in.frames.size());
  if (T < 2) throw Error(a.frames + ": holds " + std::to_string(T) + " frame; at least 2 are needed");

  // Rest shape: --garment, else the rollout's own, else the scene's.
  if (!a.garment.empty()) {
    in.garment_rest = read_mesh_in_file_order(a.garment);
  } else if (garment.rest.rows()) {
    in.garment_rest = TriMesh{garment.rest, garment.faces};
  }
  if (!a.previous.empty()) in.previous = read_mesh_in_file_order(a.previous).V;
  else if (garment.previous.rows()) in.previous = garment.previous;

  // Body: --body-frames (+ --body for a PC2's faces), else the rollout's, else the scene's.
  FrameSequence body;
  if (!a.body_frames.empty()) {
    body = read_frame_sequence(a.body_frames, "body");
    if (!a.body.empty()) body.faces = read_mesh_in_file_order(a.body).F;
    if (body.faces.rows() == 0)
      throw Error(a.body_frames + ": a point cache has no faces: give the body mesh with --body");
  } else if (file_extension(a.frames) == ".h5" || file_extension(a.frames) == ".usda") {
    try {
      body = read_frame_sequence(a.frames, "body");
    } catch (const Error&) {
      body = FrameSequence{};  // a rollout or cache without a body
    }
  }
  in.body = std::move(body.frames);
  in.body_faces = body.faces;

  std::vector<std::string> effects;
  if (!a.scene.empty()) {
    std::vector<std::string> sets = a.sets;
    sets.push_back("frames=" + std::to_string(T - 1));
    sets.push_back("outputs.mesh_format=none");
    const SceneConfig scene = load_config<SceneConfig>(a.scene, sets);
    effects = scene.effects;
    in.material = scene.material;
    in.physics = scene.physics;
    const Effects wanted = Effects::from_names(effects, a.scene + ": effects");
    if (in.garment_rest.V.rows() == 0 || (in.body.empty() && wanted.needs_body())) {
      SceneSetup setup = build_scene(scene, a.scene);
      if (in.garment_rest.V.rows() == 0) in.garment_rest = setup.garment;
      if (in.body.empty() && wanted.needs_body()) {
        in.body = setup.body;
        in.body_faces = setup.body_faces;
      }
    }
  } else {
    const ScoreConfig config = load_config<ScoreConfig>(a.config, a.sets);
    in.material = config.material;
    in.physics = config.physics;
    in.dt = 1.0 / config.fps;
    effects = config.effects;
    if (effects == std::vector<std::string>{"auto"}) {
      effects = {"gravity"};
      if (!in.body.empty()) effects.insert(effects.end(), {"collision", "friction"});
    }
  }
  in.effects = Effects::from_names(effects, a.scene.empty() ? std::string("effects") : a.scene + ": effects");
  if (in.garment_rest.V.rows() == 0)
    throw Error(a.frames + ": no rest shape: give the garment's rest mesh with --garment (or a --scene)");
  if (in.frames[0].rows() != in.garment_rest.V.rows())
    throw Error(a.frames + ": " + std::to_string(in.frames[0].rows()) + " vertices per frame, but the rest mesh " +
                (a.garment.empty() ? std::string("") : a.garment + " ") + "has " +
                std::to_string(in.garment_rest.V.rows()));
  if (!in.body.empty() && int(in.body.size()) < T)
    throw Error((a.body_frames.empty() ? a.frames : a.body_frames) + ": " + std::to_string(in.body.size()) +
                " body frames for " + std::to_string(T) + " garment frames");
  if (int(in.body.size()) > T) {
    spdlog::info("{}: scoring against the first {} of its {} frames", a.body_frames, T, in.body.size());
    in.body.resize(T);
  }
  return in;
}

}  // namespace

void add_score_command(CLI::App& app, const GlobalOptions& global) {
  auto* cmd = app.add_subcommand(
      "score",
      "Measure a cloth sequence from any tool (pb4u, Blender, ...) with the SPEC 3 terms, per frame\n"
      "and per sequence, with the same code as evaluate: stretch, bending, gravity, inertia and,\n"
      "with a body, collision, friction and the share of vertices inside the body. Frames: a PC2\n"
      "cache, simulate's rollout.h5 or scene.usda (its Garment and Body meshes), or a numbered\n"
      "OBJ/PLY sequence in the rest mesh's vertex order. Material, effects and fps from --scene\n"
      "or --config/--set (SPEC 2 defaults).\n"
      "Scoring simulate's own output reproduces its energies.csv.");
  auto args = std::make_shared<ScoreArgs>();
  cmd->add_option("--frames,-f", args->frames,
                  "The garment's frames: file.pc2, rollout.h5, scene.usda, or garment_%04d.obj / garment_*.ply")
      ->required();
  cmd->add_option("--garment,-g", args->garment,
                  "Rest mesh (OBJ/PLY, same vertex order; default: rollout.h5's, or the scene's)");
  cmd->add_option("--prev", args->previous,
                  "The garment one frame before frame 0 (OBJ/PLY; default: rollout.h5's, else frame 0 itself, "
                  "i.e. starting at rest)");
  cmd->add_option("--body-frames", args->body_frames, "The body's frames (PC2, rollout.h5, .usda, numbered OBJ/PLY)");
  cmd->add_option("--body", args->body, "The body mesh giving a body PC2 its faces (OBJ/PLY, same vertex order)");
  cmd->add_option("--scene,-s", args->scene,
                  "A scene (configs/scenes/*.yaml): material, effects and physics, and the body and rest "
                  "mesh when the files lack them");
  cmd->add_option("--config,-c", args->config, "YAML with effects, material, physics, fps (when no --scene)");
  cmd->add_option("--set", args->sets, "Override a key, e.g. --set material.mu=30000 (repeatable)");
  cmd->add_option("--format", args->format, "table | csv | json")->check(CLI::IsMember({"table", "csv", "json"}));
  cmd->add_option("--out,-o", args->out, "Write to this file instead of standard output");
  cmd->callback([args, &global] {
    apply_global_options(global);
    if (!args->scene.empty() && !args->config.empty()) throw Error("--config: give --scene or --config, not both");
    const ScoreInput in = score_input(*args);
    const ScoreResult r = score_sequence(in);
    std::string text;
    if (args->format == "csv") text = score_csv(r);
    else if (args->format == "json") text = score_json(r);
    else text = score_table(r, args->frames);
    if (args->out.empty()) {
      std::cout << text << std::flush;
    } else {
      AtomicFile file(args->out);
      file.stream() << text;
      file.commit();
      spdlog::info("wrote {}", args->out);
    }
    if (r.nonfinite_at_frame >= 0) spdlog::warn("{}: frame {} is not finite", args->frames, r.nonfinite_at_frame);
  });
}

}  // namespace pb4u

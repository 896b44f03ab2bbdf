#pragma once
// A simulation scene (SPEC 6, configs/scenes/*.yaml): a garment (a built-in template from a
// generated dataset, a mesh file, or a square cloth), an optional body and motion, a material,
// pins, effects and a frame count; turned into what a rollout needs.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "pb4u/config/config_io.h"
#include "pb4u/rollout/divergence_guard.h"
#include "pb4u/rollout/refined_step.h"
#include "pb4u/mesh/triangle_mesh.h"
#include "pb4u/scene/material.h"
#include "pb4u/physics/physics_config.h"
#include "pb4u/scene/effects.h"
#include "pb4u/scene/waistband.h"
#include "pb4u/sim/rollout_writer.h"

namespace pb4u {

struct SceneGarment {
  std::string source = "template";  // template | file | square
  std::string dataset;              // template: the generated dataset holding it
  std::string name = "tshirt";      // template: its name
  int level = 1;                    // template: resolution level (1-based)
  std::string file;                 // file: a garment mesh (OBJ, PLY, glTF...)
  int triangles = 0;                // file: remesh to about this many triangles (0: keep)
  // file: its vertices exactly as the file lists them (OBJ/PLY; no welding or clean-up), so
  // that vertex i of every output is vertex i of the file, as a DCC's point cache needs.
  bool keep_vertex_order = false;
  double size = 0.6;                // square: edge length, m
  int resolution = 20;              // square: vertices per side
  double height = 1.0;              // square: y of its top edge, m (it hangs in the xy plane)

  template <class V>
  void visit(V& v) {
    v("source", source, one_of({"template", "file", "square"}));
    v("dataset", dataset);
    v("name", name);
    v("level", level, int_at_least(1));
    v("file", file);
    v("triangles", triangles, int_at_least(0));
    v("keep_vertex_order", keep_vertex_order);
    v("size", size, positive());
    v("resolution", resolution, int_in_range(2, 1000));
    v("height", height);
  }
};

struct SceneBody {
  std::string dataset;  // generated dataset holding the body; "" = no body (unless mesh_sequence)
  // Instead of a dataset's body and motion: the body as a mesh sequence, frame t of the scene
  // on its t-th mesh (any source read_frame_sequence reads with faces: garment_%04d.obj-style
  // OBJ/PLY numbers, a .usda, a rollout .h5), m, y up. A shorter sequence holds its last mesh.
  // The garment starts where its file puts it (no skinning: pins.on_body follows the nearest
  // body vertex).
  std::string mesh_sequence;
  std::string name = "mannequin";
  // A motion of the dataset by name, "procedural:<kind>" (walk, run, jump, arm_raise,
  // torso_twist, spin) or a BVH file for the body's skeleton.
  std::string motion = "procedural:walk";
  double speed = 1.0, amplitude = 1.0;  // procedural motions
  double bvh_scale = 1.0;               // BVH file units to metres (as in generate's bvh.scale)
  double push_out_gap = 0.004;          // m: LBS start frame pushed out of the body
  // How frame 0 is reached: "skinned" (the garment skinned to the first pose and pushed
  // push_out_gap out of the body, the training data's start) or "settled" (the reference solver
  // carries the rest shape from the bind pose to the first pose in settle_steps steps, never
  // inside the body: rollout/settled_start.h). Every method of a rollout starts from it.
  std::string start = "skinned";
  int settle_steps = 10;

  template <class V>
  void visit(V& v) {
    v("dataset", dataset);
    v("mesh_sequence", mesh_sequence);
    v("name", name);
    v("motion", motion);
    v("speed", speed, positive());
    v("amplitude", amplitude, non_negative());
    v("bvh_scale", bvh_scale, positive());
    v("push_out_gap", push_out_gap, in_range(0, 0.05));
    v("start", start, one_of({"skinned", "settled"}));
    v("settle_steps", settle_steps, int_in_range(1, 1000));
  }
};

struct ScenePins {
  double top_band = 0.0;     // m: pin the vertices within this distance of the highest one
  std::vector<int> vertices;  // and these
  // With a body: the pinned vertices ride on it (the garment skinned to each frame, or with
  // body.mesh_sequence each keeps its offset to the nearest body vertex) instead of holding
  // their start positions.
  bool on_body = false;
  template <class V>
  void visit(V& v) {
    v("top_band", top_band, non_negative());
    v("vertices", vertices);
    v("on_body", on_body);
  }
};

struct SceneOutputs {
  std::string mesh_format = "obj";  // obj | ply | none
  bool point_cache = true, hdf5 = true, energies_csv = true, plot = true;
  bool usd = true;      // scene.usda: garment and body with time-sampled points (io/usd_cache.h)
  bool preview = true;  // preview.png: a contact sheet of the garment (and body)
  // Each frame's residual (energies.csv residual_mm): a Newton step of the solver from the
  // frame's step, on the CPU. Off, the column is nan; large garments on a GPU save its time.
  bool residual = true;
  // > 0: every minimum_every-th frame the reference solver goes on from the frame's step to its
  // minimum (to 0.001 mm), and energies.csv gets distance_to_minimum_mm (the largest vertex
  // move there) and energy_gap_j (how much lower the energy is there); nan on other frames.
  // The residual's yardstick: a solver's solve each sampled frame (energy_report.h).
  int minimum_every = 0;
  template <class V>
  void visit(V& v) {
    v("mesh_format", mesh_format, one_of({"obj", "ply", "none"}));
    v("preview", preview);
    v("point_cache", point_cache);
    v("usd", usd);
    v("hdf5", hdf5);
    v("energies_csv", energies_csv);
    v("plot", plot);
    v("residual", residual);
    v("minimum_every", minimum_every, int_at_least(0));
  }
};

struct SceneConfig {
  int frames = 60;
  std::vector<std::string> effects{"gravity", "collision", "friction"};
  SceneGarment garment;
  SceneBody body;
  ScenePins pins;
  // With a body, these garments' waistbands ride on it (scene/waistband.h): a skirt stays on.
  WaistbandConfig waistband;
  Material material;
  PhysicsConfig physics;
  DivergenceConfig divergence;  // when the rollout stops as diverged
  RefineConfig refine;          // the network's step refined by the reference solver (physics.solver)
  SceneOutputs outputs;

  template <class V>
  void visit(V& v) {
    v("frames", frames, int_at_least(1));
    v("effects", effects);
    v("garment", garment);
    v("body", body);
    v("pins", pins);
    v("waistband", waistband);
    v("material", material);
    v("physics", physics);
    v("divergence", divergence);
    v("refine", refine);
    v("outputs", outputs);
  }
};

// What a rollout of the scene starts from.
struct SceneSetup {
  TriMesh garment;                    // rest shape, m
  Eigen::MatrixXd x0, x_prev;         // n x 3 m: start state (LBS frame 0 with a body)
  std::vector<Eigen::MatrixXd> body;  // nb x 3 m per frame 0..frames; empty without a body
  Eigen::MatrixXi body_faces;
  std::vector<int> pinned;
  std::vector<Eigen::MatrixXd> pin_targets;  // n x 3 m per frame 0..frames when pins ride on the body
  Effects effects;
};

// Builds the scene. `scene_path` names errors and anchors relative paths (a path is tried
// as given, then relative to the scene file). Throws pb4u::Error naming the key on a scene
// that is inconsistent (e.g. collision without a body, pins without pinned vertices).
SceneSetup build_scene(const SceneConfig& scene, const std::string& scene_path);

// A square cloth of res x res vertices, `size` m wide, hanging in the xy plane with its top
// edge at y = height, centred on x = 0; alternating diagonals.
TriMesh square_cloth(double size, int res, double height);

}  // namespace pb4u

// Hard cases stay stable (issues 9, 14, 33; SPEC 9): the finest level never seen in training,
// fast motions, extreme materials, sliver and zero-area triangles, a long rollout, a body moving
// through the garment, a held-out garment on a held-out motion. Every frame of the reference
// solver (intersection-free contact where there is a body: no vertex inside it, no edge through
// it, on any frame) must be finite with non-negative energies, and no rollout may trip the
// divergence guard (positive energy 1000x its start). Edge bounds: the reference solver never
// stretches an edge past 3x rest; the shipped network neither, inside what it was trained on
// (its materials, effects and speeds, at any resolution: falling and floating cloths); outside
// it (hanging from pins, which training never samples; 3x its speeds) 10x.
// Stability, not finiteness: on every case the shipped network is held against the reference
// solver on the same scene (hard::check_relative: positive energy within 10x of the solver's,
// mean and largest frame, with no floor; with a body at most 5 points more of its vertices
// inside the body and at most 10 mm deeper). It runs four ways (hard::check_shipped): alone,
// with its inference passes, refined by 10 solver iterations a step, and refined by those and
// then on until the solver's step is below 1 mm; the last is judged, the other three print
// their figures and verdict against the same bounds. The untrained network is checked for
// finiteness only: nothing makes random weights physical. Sizes are tiny
// here; scripts/hard_cases.sh runs the same cases larger (PB4U_HARD_SCALE).
#include <gtest/gtest.h>

#include <limits>

#include "hard_case.h"
#include "pb4u/data/dataset.h"
#include "pb4u/graph/garment_topology.h"
#include "pb4u/mesh/geometry.h"
#include "pb4u/scene/pins.h"
#include "pb4u/scene/waistband.h"
#include "pb4u/sim/simulate.h"
#include "pb4u/util/error.h"
#include "pb4u/util/runtime.h"
#include "test_util.h"

namespace pb4u {
namespace {

using hard::check_rollout;

const Effects kHanging = Effects::from_names({"gravity", "pins"}, "test");
constexpr double kPhysical = 3.0;  // the reference solver; the network on its training distribution
constexpr double kNoBlowUp = 10.0; // the network outside it

struct Methods {
  double network_stretch = kPhysical;
  bool untrained = false;
};

// The reference solver, the shipped network three ways (edge bound, and bounded against the
// reference; the refined run judged) and optionally the untrained one on `in`.
void check_methods(const std::string& label, const RolloutInput& in, const Methods& m = {},
                   const PhysicsConfig& physics = {}) {
  GarmentTopology topology = build_garment_topology(in.garment_rest, label);
  const auto reference = hard::check_reference(label, in, physics);
  hard::Bounds network;
  network.max_stretch = m.network_stretch;
  hard::check_shipped(label, in, topology, physics, reference, network);
  if (m.untrained)
    check_rollout(label + " / untrained", in,
                  network_stepper(hard::untrained_model(topology.mean_edge_length), topology), physics,
                  hard::finite_only());
}

class HardCases : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { configure_threads(1); }  // tiny tensors: threads only add overhead
};

TEST_F(HardCases, FinestLevelNeverSeenInTraining) {
  // The shipped model was trained on its coarsest level only (Lbar_base); half and a quarter
  // of that edge length is the paper's Lv.4 ratio and beyond: K grows to 2 and 4 x K_base.
  const double lbar_base = hard::shipped_model().model->mean_edge_length_base();
  for (int finer : {2, 4}) {
    const int res = (4 + 2 * finer) * hard::scale();
    TriMesh cloth = test::lattice_cloth(res, res, lbar_base / finer);
    GarmentTopology topology = build_garment_topology(cloth);
    EXPECT_GE(hard::shipped_model().model->propagation_steps_for(topology.mean_edge_length),
              finer * hard::shipped_model().config.k_base - 1);
    // Falling freely (no pins, which training never samples): in the training distribution
    // but for the resolution.
    RolloutInput in = hard::still_start(cloth, Effects::from_names({"gravity"}, "test"), Material{}, 10 * hard::scale());
    check_methods("Lbar_base/" + std::to_string(finer), in, {kPhysical, finer == 4});
  }
}

// A 0.52 m square cloth hanging from its top row at half the training edge (K = 2 K_base;
// scripts/hanging_resolution.sh has a square at 1/1, 1/2 and 1/3 of it). Held to SPEC 9's 10x
// of the solver's mean positive energy (the solver's is ~0.8 mJ here, well above zero: a
// floor such as the weight x 1 cm, ~0.01 J, that check_relative once had would hide the
// failure this case is for). The model shipped before bd7d068 (2026-11-25) sagged to 38x here (the bulk of the
// cloth held at the 10% strain limit); the one fine-tuned on scenes drawn smaller is at ~6x.
TEST_F(HardCases, HangingAtHalfTheTrainingEdge) {
  const double lbar_base = hard::shipped_model().model->mean_edge_length_base();
  const int res = 40;  // vertices per side: 0.52 m at Lbar_base / 2
  TriMesh cloth = test::lattice_cloth(res, res, lbar_base / 2);
  GarmentTopology topology = build_garment_topology(cloth);
  RolloutInput in = hard::still_start(cloth, kHanging, Material{}, 30);
  const auto reference = hard::check_reference("hanging at Lbar_base/2", in, {});
  EXPECT_GT(reference.mean_positive, 1e-4);  // a stretched cloth, not one at rest
  hard::RelativeBounds mean_only;
  mean_only.max_positive_ratio = std::numeric_limits<double>::infinity();
  hard::check_shipped("hanging at Lbar_base/2", in, topology, {}, reference, {}, mean_only);
}

// The level-1 t-shirt of `dataset` (the tiny one unless given) on its mannequin doing a procedural
// motion.
SceneConfig body_scene(const std::string& motion, double speed, double amplitude, int frames,
                       const std::string& dataset = test::tiny_dataset()) {
  SceneConfig s;
  s.frames = frames;
  s.effects = {"gravity", "collision", "friction"};
  s.garment.source = "template";
  s.garment.dataset = dataset;
  s.garment.name = "tshirt";
  s.garment.level = 1;
  s.body.dataset = dataset;
  s.body.name = "mannequin";
  s.body.motion = "procedural:" + motion;
  s.body.speed = speed;
  s.body.amplitude = amplitude;
  // scripts/hard_cases.sh --start settled: the first frame reached by the solver from the bind
  // pose (rollout/settled_start.h), with the solver keys the reference runs with.
  s.body.start = hard::body_start();
  s.physics = hard::with_solver_overrides(s.physics);
  return s;
}

TEST_F(HardCases, SpinAtTwoTurnsPerSecond) {
  SceneConfig s = body_scene("spin", 4.0, 1.0, 15 * hard::scale());  // one turn; speed 1 = half a turn/s
  // Training sees speeds 0.7-1.4 (at most 0.7 turns/s): this is three times beyond.
  check_methods("spin 2 turns/s", scene_rollout_input(s, build_scene(s, "spin")), {kNoBlowUp}, s.physics);
}

// The same spin with two settings that are not the defaults (docs/robustness.md, "Why the spin
// and the jump are known gaps"): the first frame reached by the solver from the bind pose
// (body.start: settled) and the cloth riding where the body turns under it (body_carry: ride).
// Judged as every case is; the spin under the defaults stays a known gap.
TEST_F(HardCases, SpinAtTwoTurnsPerSecondSettledAndRiding) {
  SceneConfig s = body_scene("spin", 4.0, 1.0, 15 * hard::scale());
  s.body.start = "settled";
  s.physics.solver.body_carry = "ride";
  check_methods("spin 2 turns/s, settled and riding", scene_rollout_input(s, build_scene(s, "spin")), {kNoBlowUp},
                s.physics);
}

TEST_F(HardCases, FastJump) {
  SceneConfig s = body_scene("jump", 2.0, 1.3, 18 * hard::scale());  // a jump every 0.6 s, deep crouch
  check_methods("jump", scene_rollout_input(s, build_scene(s, "jump")), {kNoBlowUp}, s.physics);
}

// The spin and the jump on a t-shirt at the training resolution (configs/data/hard.yaml: the
// quick dataset's mannequin, 2949 vertices, and its level-1 t-shirt, 1961 triangles, 23 mm
// edges), under every default. The tiny t-shirt above (115 vertices, 50-140 mm edges, on a
// 400-vertex mannequin) cannot follow the armpit and the shoulders at these speeds: its cases
// are known gaps (tests/hard/known_gaps.txt).
TEST_F(HardCases, SpinAtTwoTurnsPerSecondAtTheTrainingEdge) {
  SceneConfig s = body_scene("spin", 4.0, 1.0, 15 * hard::scale(), test::hard_dataset());
  check_methods("spin 2 turns/s, training edge", scene_rollout_input(s, build_scene(s, "spin")), {kNoBlowUp},
                s.physics);
}

TEST_F(HardCases, FastJumpAtTheTrainingEdge) {
  SceneConfig s = body_scene("jump", 2.0, 1.3, 18 * hard::scale(), test::hard_dataset());
  check_methods("jump, training edge", scene_rollout_input(s, build_scene(s, "jump")), {kNoBlowUp}, s.physics);
}

TEST_F(HardCases, ExtremeMaterials) {
  const MaterialRanges r;
  struct Case {
    std::string name;
    Material m;
  };
  std::vector<Case> cases(4);
  cases[0].name = "range low ends";
  cases[0].m.density = r.density[0], cases[0].m.mu = r.mu[0], cases[0].m.lambda = r.lambda[0],
  cases[0].m.bending = r.bending[0];
  cases[1].name = "range high ends";
  cases[1].m.density = r.density[1], cases[1].m.mu = r.mu[1], cases[1].m.lambda = r.lambda[1],
  cases[1].m.bending = r.bending[1];
  cases[2].name = "10x below";
  cases[2].m = cases[0].m;
  cases[2].m.density /= 10, cases[2].m.mu /= 10, cases[2].m.lambda /= 10, cases[2].m.bending /= 10;
  cases[3].name = "10x above";
  cases[3].m = cases[1].m;
  cases[3].m.density *= 10, cases[3].m.mu *= 10, cases[3].m.lambda *= 10, cases[3].m.bending *= 10;
  const double lbar = hard::shipped_model().model->mean_edge_length_base();
  TriMesh cloth = test::lattice_cloth(6 * hard::scale(), 6 * hard::scale(), lbar);
  for (const Case& c : cases)
    check_methods("material " + c.name, hard::still_start(cloth, kHanging, c.m, 8 * hard::scale()), {kNoBlowUp});
}

TEST_F(HardCases, SliverTriangles) {
  // A strip of triangles 1e-8 m high: area ~ lbar * 0.5e-8 ~ 1e-10 m^2, rest Dm^-1 ~ 1e8 /m.
  const double lbar = hard::shipped_model().model->mean_edge_length_base();
  TriMesh cloth = test::lattice_cloth(7 * hard::scale(), 7 * hard::scale(), lbar, 3, 1e-8);
  const Eigen::VectorXd A = face_areas(cloth.V, cloth.F);
  EXPECT_LT(A.minCoeff(), 1e-9);
  EXPECT_GT(A.minCoeff(), 0.0);
  check_methods("sliver strip", hard::still_start(cloth, kHanging, Material{}, 8 * hard::scale()), {kNoBlowUp, true});
}

TEST_F(HardCases, ZeroAreaRegion) {
  // A strip of zero-area triangles: no material there (its edges are not bounded), and the
  // cloth below it hangs on nothing. Every other edge must still hold.
  const double lbar = hard::shipped_model().model->mean_edge_length_base();
  TriMesh cloth = test::lattice_cloth(7 * hard::scale(), 7 * hard::scale(), lbar, 3, 0.0);
  EXPECT_EQ(face_areas(cloth.V, cloth.F).minCoeff(), 0.0);
  check_methods("zero-area strip", hard::still_start(cloth, kHanging, Material{}, 8 * hard::scale()), {kNoBlowUp, true});
}

TEST_F(HardCases, MasslessVerticesUnderTheLastZeroAreaStrip) {
  // The bottom row touches only zero-area faces: no mass, no stiffness. The reference solver
  // must stay finite; the network needs a log mass per vertex and refuses such a garment
  // with an error naming the vertex.
  const double lbar = hard::shipped_model().model->mean_edge_length_base();
  const int res = 5 * hard::scale();
  TriMesh cloth = test::lattice_cloth(res, res, lbar, res - 2, 0.0);
  RolloutInput in = hard::still_start(cloth, kHanging, Material{}, 6 * hard::scale());
  check_rollout("massless bottom row / reference", in, reference_stepper({}), {});
  try {
    build_garment_topology(cloth, "massless");
    ADD_FAILURE() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("has no face of positive area"), std::string::npos) << e.what();
  }
}

TEST_F(HardCases, LongRollout1000Frames) {
  const int frames = 1000 * hard::scale();
  const double lbar = hard::shipped_model().model->mean_edge_length_base();
  // No body, no gravity (4% of the network's training samples): a cloth at rest, which the
  // reference solver keeps exactly at rest (zero gradient: no iteration per frame).
  TriMesh cloth = test::lattice_cloth(6 * hard::scale(), 6 * hard::scale(), lbar);
  GarmentTopology topology = build_garment_topology(cloth);
  RolloutInput floating = hard::still_start(cloth, Effects::from_names({}, "test"), Material{}, frames);
  check_rollout("long floating / untrained", floating,
                network_stepper(hard::untrained_model(topology.mean_edge_length), topology), {}, hard::finite_only());
  const auto floating_reference = hard::check_reference("long floating", floating, {});
  hard::check_shipped("long floating", floating, topology, {}, floating_reference, {});
  // Hanging from pins (which training never samples) on a tiny cloth: the reference solver
  // costs ~10 ms a frame on it.
  TriMesh small = test::lattice_cloth(3 * hard::scale(), 3 * hard::scale(), lbar);
  GarmentTopology small_topology = build_garment_topology(small);
  RolloutInput hanging = hard::still_start(small, kHanging, Material{}, frames);
  const auto hanging_reference = hard::check_reference("long hanging", hanging, {});
  hard::Bounds no_blow_up;
  no_blow_up.max_stretch = kNoBlowUp;
  hard::check_shipped("long hanging", hanging, small_topology, {}, hanging_reference, no_blow_up);
}

// A 10 cm box crosses a hanging cloth at 6 m/s (20 cm per frame), straight through it. The
// cloth it catches is carried along: its edges to the pins stretch as far as the box drags
// them (the reference solver reaches ~9x), so the bound here is kinematic: no vertex moves
// faster than twice the box.
void check_box_through_cloth(const std::string& label, const PhysicsConfig& physics) {
  const double lbar = hard::shipped_model().model->mean_edge_length_base();
  const int res = 7 * hard::scale();
  TriMesh cloth = test::lattice_cloth(res, res, lbar);
  const Eigen::Vector3d centre = cloth.V.colwise().mean().transpose();
  const double box_speed = 6.0;  // m/s
  // 6 frames: the box crosses the cloth at frame 3 and is 60 cm past it at frame 6.
  RolloutInput in = hard::still_start(cloth, Effects::from_names({"gravity", "collision", "friction", "pins"}, "test"),
                                      Material{}, 6);
  // The cloth dragged by the box gains ~1e5x its hanging energy by physics, not by blowing up.
  in.divergence.energy_ratio = 0;
  for (int f = 0; f <= in.steps; ++f) {
    Eigen::MatrixXd V;
    hard::box_mesh(centre + Eigen::Vector3d(0, 0, -0.6 + box_speed * in.dt * f), 0.05, &V, &in.body_faces);
    in.body.push_back(V);
  }
  GarmentTopology topology = build_garment_topology(cloth);
  hard::Bounds kinematic;
  kinematic.max_stretch = 0;
  kinematic.max_speed = 2 * box_speed;
  const auto reference = hard::check_reference(label, in, physics, kinematic);
  kinematic.max_stretch = kNoBlowUp;
  // Letting the box pass through the cloth is what the penetration bound catches.
  hard::check_shipped(label, in, topology, physics, reference, kinematic);
}

// The network's step went through the box: made free of it where it stands, part of the cloth
// stays on the wrong side (given_start at_step: 0.68% of the vertices inside on average). The
// default rule solves to the tolerance from its own sweep there, the box carrying the cloth.
TEST_F(HardCases, BodyMovingThroughTheGarmentFast) { check_box_through_cloth("box through cloth at 6 m/s", {}); }

TEST_F(HardCases, HeldOutGarmentOnAHeldOutMotion) {
  // The shipped model was trained on the quick dataset: the tiny dataset's skirt (another mesh)
  // on its mannequin, doing one of its test-split motions, is a garment, body and motion it
  // never saw. It left the known-gap list with the contact projection (docs/log/).
  const Dataset data = read_dataset(test::tiny_dataset());
  const BodyRecord* record = data.find_body("mannequin");
  ASSERT_NE(record, nullptr);
  const Garment* skirt = nullptr;
  for (const auto& g : record->garments)
    if (g.name == "skirt") skirt = &g.levels.front();
  ASSERT_NE(skirt, nullptr);
  const MotionRecord* motion = nullptr;
  for (const auto& m : data.motions)
    if (m.split == "test" && m.body == record->body.name && !motion) motion = &m;
  ASSERT_NE(motion, nullptr);
  const int start = 1, steps = std::min(10 * hard::scale(), motion->motion.num_frames() - 1 - start);
  RolloutInput in = lbs_rollout_input(record->body, *skirt, motion->motion, start, steps,
                                      Effects::from_names({"gravity", "collision", "friction"}, "test"), Material{},
                                      0.004);
  // Held at the waist, as evaluation and scenes hold skirts (scene/waistband.h): without the
  // grip the solver's skirt falls off the mannequin and there is nothing to compare against.
  const WaistbandConfig waistband;
  in.effects.pins = true;
  in.pinned = top_band_vertices(skirt->mesh.V, waistband.band);
  in.pin_targets = skinned_pin_targets(record->body, *skirt, motion->motion, start, in.body, 0.004);
  EXPECT_EQ(hold_pins_free_of_body(in), 0);  // no waistband edge through the body: the pins can be met
  check_methods("skirt on test motion " + motion->name, in, {kNoBlowUp});
}

}  // namespace
}  // namespace pb4u

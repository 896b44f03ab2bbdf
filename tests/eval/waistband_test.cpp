// Garments held at the waist (scene/waistband.h): on a body a skirt's waistband rides on the
// skinned garment in rollouts, evaluation and scenes; without the grip the reference solver
// lets the skirt fall off the body.
#include <gtest/gtest.h>

#include "pb4u/data/dataset.h"
#include "pb4u/data/lbs_frame.h"
#include "pb4u/eval/evaluate.h"
#include "pb4u/mesh/edges.h"
#include "pb4u/physics/barrier_potential.h"
#include "pb4u/rollout/rollout.h"
#include "pb4u/physics/reference_solver.h"
#include "pb4u/scene/pins.h"
#include "pb4u/sim/scene.h"
#include "pb4u/util/error.h"
#include "pb4u/util/runtime.h"
#include "test_util.h"

namespace pb4u {
namespace {

using test::kSource;

struct SkirtOnAWalk {
  Dataset data;
  const BodyRecord* record = nullptr;
  const Garment* skirt = nullptr;
  const MotionRecord* motion = nullptr;
};

SkirtOnAWalk skirt_on_a_walk() {
  configure_threads(1);
  SkirtOnAWalk s;
  s.data = read_dataset(test::tiny_dataset());
  s.record = s.data.find_body("mannequin");
  for (const auto& g : s.record->garments)
    if (g.name == "skirt") s.skirt = &g.levels.at(0);
  for (const auto& m : s.data.motions)
    if (m.body == "mannequin" && m.source == "procedural:walk" && !s.motion) s.motion = &m;
  return s;
}

// `steps` frames of the walk from `start`, the skirt's top 2 cm pinned to the garment skinned
// to each frame.
RolloutInput pinned_skirt_rollout(const SkirtOnAWalk& s, int start, int steps) {
  Effects effects;
  effects.pins = true;
  RolloutInput in = lbs_rollout_input(s.record->body, *s.skirt, s.motion->motion, start, steps, effects, Material{},
                                      0.004);
  in.pinned = top_band_vertices(s.skirt->mesh.V, 0.02);
  in.pin_targets = skinned_pin_targets(s.record->body, *s.skirt, s.motion->motion, start, in.body, 0.004);
  return in;
}

TEST(Waistband, HoldsTheListedGarmentsOnly) {
  WaistbandConfig w;
  EXPECT_TRUE(w.holds("skirt"));
  EXPECT_FALSE(w.holds("tshirt"));
  w.band = 0;
  EXPECT_FALSE(w.holds("skirt"));
  EXPECT_FALSE((WaistbandConfig{{}, 0.02}).holds("skirt"));
}

TEST(Waistband, PinsHeldFreeOfTheBodyStartWhereTheirFirstTargetsAre) {
  const SkirtOnAWalk s = skirt_on_a_walk();
  ASSERT_TRUE(s.skirt && s.motion);
  RolloutInput in = pinned_skirt_rollout(s, 1, 4);
  const RolloutInput skinned = in;
  EXPECT_EQ(hold_pins_free_of_body(in), 0);
  const Eigen::MatrixXi edges = unique_edges(s.skirt->mesh.F);
  double most = 0;
  for (size_t k = 0; k < in.pin_targets.size(); ++k) {
    const ContactSurface body = make_contact_surface(in.body[k], in.body_faces);
    std::vector<char> pinned(size_t(in.x0.rows()), 0);
    for (int i : in.pinned) pinned[size_t(i)] = 1;
    for (int e : cloth_edges_through_body(in.pin_targets[k], edges, body))
      EXPECT_FALSE(pinned[size_t(edges(e, 0))] && pinned[size_t(edges(e, 1))]) << "frame " << k << ", edge " << e;
    most = std::max(most, (in.pin_targets[k] - skinned.pin_targets[k]).rowwise().norm().maxCoeff());
  }
  // The skinned targets' chords cut this mannequin's waist: the pins did move, the start with them.
  EXPECT_GT(most, 1e-3);
  EXPECT_LT((in.pin_targets[0] - in.x0).norm(), 1e-12);
  for (Eigen::Index i = 0; i < in.x0.rows(); ++i) {
    const Eigen::RowVector3d moved = in.x0.row(i) - skinned.x0.row(i);
    EXPECT_LT((in.x_prev.row(i) - skinned.x_prev.row(i) - moved).norm(), 1e-12) << i;
  }
}

TEST(Waistband, PinnedVerticesRideOnTheSkinnedGarmentInARollout) {
  const SkirtOnAWalk s = skirt_on_a_walk();
  ASSERT_TRUE(s.skirt && s.motion);
  const int start = 1, steps = 4;
  RolloutInput in = pinned_skirt_rollout(s, start, steps);
  ASSERT_FALSE(in.pinned.empty());
  ASSERT_EQ(in.pin_targets.size(), size_t(steps + 1));
  // The targets are the skinned, pushed-out garment of each frame: frame 0 is the start state.
  EXPECT_LT((in.pin_targets[0] - in.x0).norm(), 1e-12);
  PhysicsConfig physics;
  physics.solver.max_iterations = 20;
  double moved = 0;
  RolloutResult r = run_rollout(in, reference_stepper(physics.solver), physics,
                                [&](int frame, const Eigen::MatrixXd& x, const EnergyReport&, const PenetrationFigures*) {
                                  for (int i : in.pinned) {
                                    EXPECT_LT((x.row(i) - in.pin_targets[frame].row(i)).norm(), 1e-9) << frame << " " << i;
                                    moved = std::max(moved, (x.row(i) - in.x0.row(i)).norm());
                                  }
                                });
  ASSERT_EQ(r.reports.size(), size_t(steps));
  EXPECT_GT(moved, 1e-3);  // the walk moves the hips: the pins moved with them
  // Too few frames of targets is an error, not a silent hold.
  in.pin_targets.pop_back();
  EXPECT_THROW(run_rollout(in, reference_stepper(physics.solver), physics), Error);
}

TEST(Waistband, EvaluationKeepsTheSkirtOnTheBodyWhereItWouldFallOff) {
  const std::string dataset = test::tiny_dataset();
  auto mean_gravity = [&](const std::string& garments) {
    const EvalConfig config = load_config<EvalConfig>(
        kSource + "/configs/eval/tiny.yaml", {"dataset=" + dataset, "levels=[1]", "garments=[skirt]", "max_frames=8",
                                              "max_sequences=1", "physics.solver.max_iterations=30",
                                              "waistband.garments=" + garments});
    auto levels = evaluate(config, {{"Reference", nullptr}});
    const SequenceResult& q = levels.at(0).methods.at(0).per_sequence.at(0);
    EXPECT_EQ(q.garment, "skirt");
    EXPECT_TRUE(q.mean && q.mean->has("gravity"));
    return q.mean->value("gravity");
  };
  const double held = mean_gravity("[skirt]"), loose = mean_gravity("[]");
  // Gravity energy is m g y: the skirt's weight times 2 cm is the least gap we accept.
  const SkirtOnAWalk s = skirt_on_a_walk();
  double area = 0;
  const TriMesh& m = s.skirt->mesh;
  for (int f = 0; f < m.F.rows(); ++f) {
    const Eigen::Vector3d a = m.V.row(m.F(f, 1)) - m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 2)) - m.V.row(m.F(f, 0));
    area += 0.5 * a.cross(b).norm();
  }
  const double weight = area * Material{}.density * 9.81;
  EXPECT_GT(held - loose, 0.02 * weight) << "held " << held << " J, loose " << loose << " J, weight " << weight << " N";
}

TEST(Waistband, SceneWithABodyPinsASkirtsWaistbandOnly) {
  const std::string dataset = test::tiny_dataset();
  auto setup_of = [&](const std::string& garment, bool waistband) {
    SceneConfig scene;
    scene.frames = 3;
    scene.garment.source = "template";
    scene.garment.dataset = dataset;
    scene.garment.name = garment;
    scene.body.dataset = dataset;
    scene.body.name = "mannequin";
    scene.body.motion = "procedural:walk";
    if (!waistband) scene.waistband.garments.clear();
    return build_scene(scene, "scene.yaml");
  };
  SceneSetup skirt = setup_of("skirt", true);
  EXPECT_TRUE(skirt.effects.pins);
  EXPECT_FALSE(skirt.pinned.empty());
  ASSERT_EQ(skirt.pin_targets.size(), 4u);
  EXPECT_GT((skirt.pin_targets[3] - skirt.pin_targets[0]).norm(), 0.0);
  SceneSetup loose = setup_of("skirt", false);
  EXPECT_FALSE(loose.effects.pins);
  EXPECT_TRUE(loose.pinned.empty() && loose.pin_targets.empty());
  SceneSetup tshirt = setup_of("tshirt", true);
  EXPECT_FALSE(tshirt.effects.pins);
  EXPECT_TRUE(tshirt.pinned.empty() && tshirt.pin_targets.empty());
}

}  // namespace
}  // namespace pb4u

// A model file's own refinement (ModelConfig::refine_*, rollout.h's network_stepper): the file
// stores the count, the tolerance and the contact; the refinement's other keys (refine.step,
// refine.release_held_cloth) come from the scene's or config's refine section, so the file
// refines exactly as the same network refined by that section would.
#include <gtest/gtest.h>

#include "pb4u/graph/garment_topology.h"
#include "pb4u/rollout/refined_step.h"
#include "pb4u/rollout/rollout.h"
#include "pb4u/util/eigen_tensor.h"
#include "physics_test_util.h"

namespace pb4u {
namespace {

TEST(FileRefinement, ReadsTheRefineKeysTheFileDoesNotStore) {
  // A cloth sunk 2 cm into a sphere, advanced 2 frames by a small untrained network refined 2
  // iterations a frame with barrier contact: by the file's own refinement, and by the same
  // network without one refined by a refine section with the same count. Newton and
  // quasi-Newton steps end apart after 2 iterations, so a file that ignored refine.step would
  // match one of the two rows only.
  TriMesh garment;
  const FrameState start = test::cloth_above_sphere(6, 0.4, 0.3, -0.02, 2, &garment);
  const TriMesh sphere = test::icosphere(0.3, 2, Eigen::RowVector3d::Zero());
  RolloutInput in;
  in.garment_rest = garment;
  in.x0 = in.x_prev = tensor_to_matrix(start.x);
  in.effects = start.effects;
  in.steps = 2;
  in.body.assign(in.steps + 1, sphere.V);
  in.body_faces = sphere.F;
  const GarmentTopology topology = build_garment_topology(garment);
  torch::manual_seed(5);
  ModelFile plain;
  plain.config.latent = 16;
  plain.config.num_blocks = 1;
  plain.model = Pb4uNet(plain.config);
  plain.model->calibrate(topology.mean_edge_length);
  plain.model->eval();
  ModelFile refining = plain;
  refining.config.refine_iterations = 2;
  refining.config.refine_contact = "barrier";
  PhysicsConfig physics;
  physics.solver.contact = "barrier";

  auto last_frame = [&](const StepFunction& step) {
    Eigen::MatrixXd last;
    run_rollout(in, step, physics, [&](int, const Eigen::MatrixXd& x, const EnergyReport&, const PenetrationFigures*) {
      last = x;
    });
    return last;
  };
  std::vector<Eigen::MatrixXd> by_file;
  for (const std::string step : {"newton", "quasi_newton"}) {
    SCOPED_TRACE(step);
    RefineConfig keys;
    keys.step = step;
    keys.release_held_cloth = step == "newton";  // both values read, each with a step kind
    const Eigen::MatrixXd file = last_frame(network_stepper(refining, topology, -1, nullptr, physics.solver, keys));
    RefineConfig section = keys;
    section.iterations = 2;
    const Eigen::MatrixXd config =
        last_frame(refined_stepper(network_stepper(plain, topology), physics.solver, section));
    ASSERT_EQ(file.rows(), garment.V.rows());
    EXPECT_EQ((file - config).cwiseAbs().maxCoeff(), 0.0);
    by_file.push_back(file);
  }
  EXPECT_GT((by_file[0] - by_file[1]).cwiseAbs().maxCoeff(), 1e-9) << "the two steps must end apart for the test to tell";
}

}  // namespace
}  // namespace pb4u

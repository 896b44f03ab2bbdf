#pragma once
// Inference-time constraints on a network's step, as a model's config asks for them: strain
// limiting (model.strain_limit, physics/strain_limiting.h) and the contact projection
// (model.contact_projection, physics/contact_projection.h). The two disagree where a limb has
// moved into the cloth: the projection pushes the vertices it overran out of the body and
// stretches their edges; the limit pulls them back in. They alternate, limit then project,
// until the projected step keeps every edge within 1.1x the strain limit or `max_rounds` run
// out; the step always ends projected. With the strain limit off it is the projection alone.
#include <torch/torch.h>

#include "pb4u/physics/body_queries.h"
#include "pb4u/scene/frame_state.h"

namespace pb4u {

struct GarmentTopology;

// x_next: (n, 3) m, the network's step from `state`; contact: the step's body contact or null.
// Returns x_next constrained (same dtype and device).
torch::Tensor constrain_step(const torch::Tensor& x_next, const FrameState& state, const BodyContact* contact,
                             const GarmentTopology& topology, double strain_limit, double gap, int max_rounds = 10);

}  // namespace pb4u

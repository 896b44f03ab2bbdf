#include "pb4u/physics/step_constraints.h"

#include <optional>

#include "pb4u/physics/contact_projection.h"
#include "pb4u/physics/strain_limiting.h"

namespace pb4u {

torch::Tensor constrain_step(const torch::Tensor& x_next, const FrameState& state, const BodyContact* contact,
                             const GarmentTopology& topology, double strain_limit, double gap, int max_rounds) {
  if (!(strain_limit > 0)) return project_out_of_body(x_next, state, contact, gap);
  const bool projects = gap > 0 && state.body.defined() && state.body.next_vertices.defined();
  torch::Tensor x = x_next;
  // Every round queries the same body: its surface is prepared once.
  std::optional<ProjectionSurface> surface;
  if (projects) surface.emplace(state.body);
  for (int round = 0; round < max_rounds; ++round) {
    x = limit_edge_strain(x, topology, state.pinned, strain_limit).x;
    if (!projects) break;
    x = project_out_of_body(x, state, contact, gap, &*surface);
    // Measured only (no sweeps): did the projection stretch an edge past the limit?
    if (limit_edge_strain(x, topology, state.pinned, strain_limit, 0).max_strain <= 1.1 * strain_limit) break;
  }
  return x;
}

}  // namespace pb4u

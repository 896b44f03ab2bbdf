#pragma once
// Turns one frame of a garment into the network's graph (SPEC 4): the one place that says what
// goes into the network.
#include "pb4u/graph/garment_topology.h"
#include "pb4u/graph/graph_batch.h"
#include "pb4u/graph/graph_options.h"
#include "pb4u/scene/frame_state.h"

namespace pb4u {

// Vertex features (21): velocity v_t (3, m/s), normal (3), type one-hot garment/body/pinned (3),
// log mass (1, log kg; 0 for body nodes), normalised material (4), effect flags gravity /
// collision / friction / pins (4), gravity vector (3, m/s^2; zero when gravity is off).
// World edges exist only when the effects need a body and one is given; both directions.
// Body nodes are the body vertices world edges touch, after the garment's, in first-touch order.
// Throws pb4u::Error ("frame state: ...") on shapes that do not match the topology or
// non-finite positions.
GraphBatch build_graph(const FrameState& state, const GarmentTopology& topology,
                       const GraphOptions& options);

}  // namespace pb4u

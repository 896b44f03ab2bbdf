#pragma once
// Several garments' graphs as one disjoint graph, so a training step runs one forward over a
// batch. Per-graph outputs come back with torch::split_with_sizes(a, garment node counts).
#include <vector>

#include "pb4u/graph/graph_batch.h"

namespace pb4u {

// Garment nodes of every graph first (in order), then every graph's body nodes, keeping the
// GraphBatch invariant the model relies on; edge indices are renumbered. mean_edge_length is
// the mean rest length over all the graphs' unique edges. body_vertex_index keeps each graph's
// own body numbering. Throws pb4u::Error on an empty list.
GraphBatch concat_graphs(const std::vector<GraphBatch>& graphs);

}  // namespace pb4u

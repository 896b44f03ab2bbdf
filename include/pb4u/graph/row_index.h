#pragma once
// Gathering rows by an index and summing rows back at it: the two halves of message passing,
// and of each other's backward pass.
//
// libtorch 1.13 sums rows on the CPU (index_add_, also the backward of index_select) one row
// at a time through tensor views: 176 us for 6000 rows of 64 floats on one core, 7x a gather
// of the same rows. A RowIndex groups the entries of an index by the row they point at
// (CSR, built once per index), so that a sum visits each output row once, in parallel over
// rows, adding its entries in increasing entry order: the same order, hence the same bits, as
// index_add_. gather_rows and sum_rows_at are differentiable, each the other's backward.
//
// A RowIndex without groups (made from a bare tensor, or on a GPU, where torch's own kernels
// are fast) falls back to index_select and index_add_.
#include <torch/torch.h>

#include <cstdint>

namespace pb4u {

struct RowIndex {
  torch::Tensor index;    // (E) int64: the row each entry points at
  torch::Tensor order;    // (E) int64, CPU: the entries sorted by row (stable); undefined: no groups
  torch::Tensor offsets;  // (rows + 1) int64, CPU: row i's entries are order[offsets[i] .. offsets[i+1])

  RowIndex() = default;
  // No groups: gather_rows and sum_rows_at use torch's kernels on it.
  RowIndex(torch::Tensor bare) : index(std::move(bare)) {}  // NOLINT: a bare index is a RowIndex
  bool grouped() const { return order.defined(); }
  // Rows the groups cover (indices must lie below it); 0 without groups.
  int64_t rows() const { return offsets.defined() ? offsets.size(0) - 1 : 0; }
};

// Groups `index` (E, int64, every entry in [0, rows)) by row. A CPU index gets its groups; an
// index on another device stays bare. Throws pb4u::Error on an entry outside [0, rows).
RowIndex group_rows(const torch::Tensor& index, int64_t rows);

// x.index_select(0, ix.index): (E, C...) from x (rows, C...).
torch::Tensor gather_rows(const torch::Tensor& x, const RowIndex& ix);

// zeros(rows, C...).index_add_(0, ix.index, values): each of the `rows` rows the sum of the
// entries pointing at it. `rows` may exceed ix.rows() (the extra rows are zero).
torch::Tensor sum_rows_at(const torch::Tensor& values, const RowIndex& ix, int64_t rows);

}  // namespace pb4u

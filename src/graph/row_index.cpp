#include "pb4u/graph/row_index.h"

#include <ATen/Parallel.h>

#include <algorithm>
#include <string>
#include <vector>

#include "pb4u/util/error.h"

namespace pb4u {
namespace {

using torch::autograd::AutogradContext;
using torch::autograd::variable_list;

// The grouped sum: out[i] = sum over row i's entries e, in increasing e, of values[e].
// values (E, C) contiguous on the CPU; out (rows_out, C) with rows_out >= ix.rows().
torch::Tensor grouped_sum(const torch::Tensor& values, const RowIndex& ix, int64_t rows_out) {
  int64_t C = 1;  // values per row, whatever the row's shape (and with no rows at all)
  for (int64_t d = 1; d < values.dim(); ++d) C *= values.size(d);
  const auto flat = values.contiguous().view({values.size(0), C});
  const int64_t rows = ix.rows();
  torch::Tensor out = torch::zeros({rows_out, C}, flat.options());
  const int64_t* order = ix.order.data_ptr<int64_t>();
  const int64_t* offsets = ix.offsets.data_ptr<int64_t>();
  AT_DISPATCH_FLOATING_TYPES(flat.scalar_type(), "sum_rows_at", [&] {
    const scalar_t* src = flat.data_ptr<scalar_t>();
    scalar_t* dst = out.data_ptr<scalar_t>();
    // ~64 rows of 64 values make a chunk worth a thread.
    const int64_t grain = std::max<int64_t>(1, 4096 / std::max<int64_t>(1, C));
    at::parallel_for(0, rows, grain, [&](int64_t begin, int64_t end) {
      for (int64_t i = begin; i < end; ++i) {
        scalar_t* d = dst + i * C;
        for (int64_t k = offsets[i]; k < offsets[i + 1]; ++k) {
          const scalar_t* s = src + order[k] * C;
          for (int64_t c = 0; c < C; ++c) d[c] += s[c];
        }
      }
    });
  });
  auto shape = values.sizes().vec();
  shape[0] = rows_out;
  return out.view(shape);
}

torch::Tensor plain_sum(const torch::Tensor& values, const torch::Tensor& index, int64_t rows_out) {
  auto shape = values.sizes().vec();
  shape[0] = rows_out;
  return torch::zeros(shape, values.options()).index_add_(0, index, values);
}

bool use_groups(const torch::Tensor& t, const RowIndex& ix) {
  return ix.grouped() && t.device().is_cpu() && at::isFloatingType(t.scalar_type());
}

RowIndex index_of(AutogradContext* ctx) {
  RowIndex ix;
  ix.index = ctx->saved_data["index"].toTensor();
  ix.order = ctx->saved_data["order"].toTensor();
  ix.offsets = ctx->saved_data["offsets"].toTensor();
  return ix;
}

void save_index(AutogradContext* ctx, const RowIndex& ix) {
  ctx->saved_data["index"] = ix.index;
  ctx->saved_data["order"] = ix.order;
  ctx->saved_data["offsets"] = ix.offsets;
}

// Both functions save the index, not the inputs: each one's backward is the other's forward.
struct GatherRowsFunction : torch::autograd::Function<GatherRowsFunction> {
  static torch::Tensor forward(AutogradContext* ctx, const torch::Tensor& x, const RowIndex& ix) {
    save_index(ctx, ix);
    ctx->saved_data["rows"] = x.size(0);
    return x.index_select(0, ix.index);
  }
  static variable_list backward(AutogradContext* ctx, variable_list grad) {
    return {sum_rows_at(grad[0], index_of(ctx), ctx->saved_data["rows"].toInt()), torch::Tensor()};
  }
};

struct SumRowsAtFunction : torch::autograd::Function<SumRowsAtFunction> {
  static torch::Tensor forward(AutogradContext* ctx, const torch::Tensor& values, const RowIndex& ix,
                               int64_t rows) {
    save_index(ctx, ix);
    return grouped_sum(values, ix, rows);
  }
  static variable_list backward(AutogradContext* ctx, variable_list grad) {
    return {gather_rows(grad[0], index_of(ctx)), torch::Tensor(), torch::Tensor()};
  }
};

}  // namespace

RowIndex group_rows(const torch::Tensor& index, int64_t rows) {
  RowIndex ix(index);
  if (!index.device().is_cpu()) return ix;
  const auto idx = index.to(torch::kInt64).contiguous();
  ix.index = idx;
  const int64_t E = idx.size(0);
  const int64_t* p = idx.data_ptr<int64_t>();
  auto offsets = torch::zeros({rows + 1}, torch::kInt64);
  int64_t* off = offsets.data_ptr<int64_t>();
  for (int64_t e = 0; e < E; ++e) {
    if (p[e] < 0 || p[e] >= rows)
      throw Error("group_rows: entry " + std::to_string(e) + " points at row " + std::to_string(p[e]) +
                  ", outside [0, " + std::to_string(rows) + ")");
    ++off[p[e] + 1];
  }
  for (int64_t i = 0; i < rows; ++i) off[i + 1] += off[i];
  // Counting sort: stable, so each row's entries stay in increasing order.
  auto order = torch::empty({E}, torch::kInt64);
  int64_t* o = order.data_ptr<int64_t>();
  std::vector<int64_t> next(off, off + rows);
  for (int64_t e = 0; e < E; ++e) o[next[p[e]]++] = e;
  ix.order = order;
  ix.offsets = offsets;
  return ix;
}

// Fewer rows than the groups cover: torch's kernels, which check every entry against them.
torch::Tensor gather_rows(const torch::Tensor& x, const RowIndex& ix) {
  if (!use_groups(x, ix) || x.size(0) < ix.rows()) return x.index_select(0, ix.index);
  return GatherRowsFunction::apply(x, ix);
}

torch::Tensor sum_rows_at(const torch::Tensor& values, const RowIndex& ix, int64_t rows) {
  if (!use_groups(values, ix) || rows < ix.rows()) return plain_sum(values, ix.index, rows);
  return SumRowsAtFunction::apply(values, ix, rows);
}

}  // namespace pb4u

#pragma once
// bench's results as files and text: bench.csv (SPEC 7), the detailed and per-stage CSVs, and
// the Table 3 layout with the equal-loss speed-ups and latency exponents read off the rows.
#include <string>
#include <vector>

#include "pb4u/eval/bench.h"

namespace pb4u {

// SPEC 7: level,triangles,vertices,method,K,threads,latency_ms_median,latency_ms_min,physics_loss
std::string format_bench_csv(const BenchResult& result);
// Every column of every row, terms and (with a body) penetration included (for plots and
// scripts).
std::string format_bench_details_csv(const BenchResult& result);
std::string format_stages_csv(const BenchResult& result);
// Table 3 layout: per level, one row per method with K, latency, total and positive loss;
// then the per-stage table, the FLOP-rate comparison, the Pb4U-vs-reference speed-up at equal
// loss and the fitted latency exponents.
std::string format_bench_table(const BenchResult& result);

// The fastest run of `family` at `net`'s level whose positive energy (stretch + bending +
// collision, per frame) is at or below the network's, or null.
// A run the divergence guard stopped does not count: its loss covers only the frames before the
// stop.
const BenchRow* cheapest_at_equal_loss(const std::vector<BenchRow>& rows, const BenchRow& net,
                                       const std::string& family);

// Least-squares slope of log(latency) on log(vertices) over the rows of `method` (NaN if
// fewer than two levels).
double latency_exponent(const std::vector<BenchRow>& rows, const std::string& method);

}  // namespace pb4u

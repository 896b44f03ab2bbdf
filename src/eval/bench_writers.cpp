#include "pb4u/eval/bench_writers.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "pb4u/util/number_format.h"

namespace pb4u {
namespace {

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string csv_number(double v) { return significant(v, 6, "nan"); }

}  // namespace

std::string format_bench_csv(const BenchResult& result) {
  std::ostringstream out;
  out << "level,triangles,vertices,method,K,threads,latency_ms_median,latency_ms_min,physics_loss\n";
  for (const auto& r : result.rows)
    out << r.level << ',' << r.triangles << ',' << r.vertices << ',' << csv_field(r.method) << ',' << r.K << ','
        << r.threads << ',' << csv_number(r.latency_ms_median) << ',' << csv_number(r.latency_ms_min) << ','
        << csv_number(r.physics_loss) << '\n';
  return out.str();
}

std::string format_bench_details_csv(const BenchResult& result) {
  static const char* kTerms[] = {"stretch", "bending", "collision", "inertia", "gravity", "friction", "repulsion"};
  std::ostringstream out;
  out << "level,triangles,vertices,method,family,K,iterations,threads,latency_ms_median,latency_ms_min,"
         "physics_loss,positive_loss";
  for (const char* t : kTerms) out << ',' << t;
  out << ",frames,diverged,diverged_at_frame,penetrating_fraction,max_penetrating_fraction,max_penetration_mm,"
         "residual_mm_median,distance_to_minimum_mm_median,distance_to_minimum_mm_max,energy_gap_j_median\n";
  for (const auto& r : result.rows) {
    out << r.level << ',' << r.triangles << ',' << r.vertices << ',' << csv_field(r.method) << ',' << r.family
        << ',' << r.K << ',' << r.iterations << ',' << r.threads << ',' << csv_number(r.latency_ms_median) << ','
        << csv_number(r.latency_ms_min) << ',' << csv_number(r.physics_loss) << ',' << csv_number(r.positive_loss);
    for (const char* t : kTerms) {
      double v = NAN;
      for (const auto& [name, value] : r.terms)
        if (name == t) v = value;
      out << ',' << (std::isnan(v) ? std::string() : csv_number(v));
    }
    out << ',' << r.frames << ',' << (r.diverged ? "true" : "false") << ',' << r.diverged_at_frame;
    for (double PenetrationSummary::*field : {&PenetrationSummary::penetrating_fraction,
                                             &PenetrationSummary::max_penetrating_fraction,
                                             &PenetrationSummary::max_penetration_mm})
      out << ',' << (r.penetration ? csv_number((*r.penetration).*field) : std::string());
    out << ',' << csv_number(r.residual_mm_median);
    for (double MinimumSummary::*field : {&MinimumSummary::distance_median_mm, &MinimumSummary::distance_max_mm,
                                          &MinimumSummary::gap_median_j})
      out << ',' << (r.minimum.frames > 0 ? csv_number(r.minimum.*field) : std::string());
    out << '\n';
  }
  return out.str();
}

std::string format_stages_csv(const BenchResult& result) {
  std::ostringstream out;
  out << "level,vertices,mesh_edges,world_edges,method,body,K,graph_build_ms,world_edge_query_ms,encode_ms,"
         "propagate_ms,blocks_ms,decode_ms,euler_ms,contact_query_ms,physics_terms_ms,message_passing_gflops,"
         "matmul_gflops\n";
  for (const auto& s : result.stages)
    out << s.level << ',' << s.vertices << ',' << s.mesh_edges << ',' << s.world_edges << ','
        << csv_field(s.method) << ',' << (s.with_body ? "true" : "false") << ',' << s.K << ','
        << csv_number(s.graph_build) << ',' << csv_number(s.world_edge_query) << ',' << csv_number(s.encode) << ','
        << csv_number(s.propagate) << ',' << csv_number(s.blocks) << ',' << csv_number(s.decode) << ','
        << csv_number(s.euler) << ',' << csv_number(s.contact_query) << ',' << csv_number(s.physics_terms) << ','
        << csv_number(s.message_passing_gflops) << ',' << csv_number(s.matmul_gflops) << '\n';
  return out.str();
}

const BenchRow* cheapest_at_equal_loss(const std::vector<BenchRow>& rows, const BenchRow& net,
                                       const std::string& family) {
  const BenchRow* best = nullptr;
  for (const auto& r : rows)
    if (r.level == net.level && r.family == family && !r.diverged && std::isfinite(r.positive_loss) &&
        r.positive_loss <= net.positive_loss && (!best || r.latency_ms_median < best->latency_ms_median))
      best = &r;
  return best;
}

double latency_exponent(const std::vector<BenchRow>& rows, const std::string& method) {
  std::vector<double> x, y;
  for (const auto& r : rows)
    if (r.method == method && r.vertices > 0 && r.latency_ms_median > 0 && std::isfinite(r.latency_ms_median)) {
      x.push_back(std::log(double(r.vertices)));
      y.push_back(std::log(r.latency_ms_median));
    }
  if (x.size() < 2) return NAN;
  double mx = 0, my = 0;
  for (size_t i = 0; i < x.size(); ++i) mx += x[i], my += y[i];
  mx /= double(x.size());
  my /= double(y.size());
  double sxy = 0, sxx = 0;
  for (size_t i = 0; i < x.size(); ++i) sxy += (x[i] - mx) * (y[i] - my), sxx += (x[i] - mx) * (x[i] - mx);
  return sxx > 0 ? sxy / sxx : NAN;
}

std::string format_bench_table(const BenchResult& result) {
  std::ostringstream out;
  out << "Accuracy vs time (" << result.device << ", " << result.threads << " torch threads, BLAS "
      << result.blas_core << "); latency per frame after warm-up, loss = mean physics energy per frame (J);\n"
         "residual mm = median over frames of the step's residual (how far from the energy's minimum, one Newton step)\n";
  std::vector<int> levels;
  for (const auto& r : result.rows)
    if (std::find(levels.begin(), levels.end(), r.level) == levels.end()) levels.push_back(r.level);
  std::vector<std::string> methods;
  for (const auto& r : result.rows)
    if (std::find(methods.begin(), methods.end(), r.method) == methods.end()) methods.push_back(r.method);
  size_t w = 8;
  for (const auto& m : methods) w = std::max(w, m.size());
  bool sampled = false;  // minimum_every: the median distance to the minimum per row
  for (const auto& r : result.rows) sampled = sampled || r.minimum.frames > 0;
  if (sampled)
    out << "to min. mm = median over the frames sampled with minimum_every of the largest vertex move from the\n"
           "step to the minimum the solver reaches from it\n";
  char line[256];
  for (int level : levels) {
    const BenchRow* first = nullptr;
    for (const auto& r : result.rows)
      if (r.level == level) {
        first = first ? first : &r;
      }
    out << "\nLv." << level << "  (" << first->triangles << " triangles, " << first->vertices << " vertices)\n";
    std::snprintf(line, sizeof line, "  %-*s %4s %12s %12s %12s %12s %12s%s\n", int(w), "method", "K", "median ms",
                  "min ms", "total J", "positive J", "residual mm", sampled ? "   to min. mm" : "");
    out << line;
    for (const auto& r : result.rows) {
      if (r.level != level) continue;
      std::string note = r.diverged ? "  diverged at frame " + std::to_string(r.diverged_at_frame) : "";
      char to_minimum[32] = "";
      if (sampled)
        std::snprintf(to_minimum, sizeof to_minimum, " %12s",
                      r.minimum.frames > 0 ? fixed(r.minimum.distance_median_mm, 2).c_str() : "n/a");
      std::snprintf(line, sizeof line, "  %-*s %4lld %12s %12s %12s %12s %12s%s%s\n", int(w), r.method.c_str(),
                    static_cast<long long>(r.K), fixed(r.latency_ms_median, 1).c_str(),
                    fixed(r.latency_ms_min, 1).c_str(), scientific(r.physics_loss, 3).c_str(),
                    scientific(r.positive_loss, 3).c_str(),
                    std::isfinite(r.residual_mm_median) ? scientific(r.residual_mm_median, 2).c_str() : "n/a",
                    to_minimum, note.c_str());
      out << line;
    }
  }

  if (!result.stages.empty()) {
    out << "\nPer-stage time of one frame (ms, median); MP = message passing (propagation + update + "
           "blocks) FLOP rate\n";
    std::snprintf(line, sizeof line, "  %-3s %-*s %3s %6s %6s %6s %6s %6s %6s %6s %6s %7s %7s %8s\n", "Lv.",
                  int(w), "method", "K", "graph", "world", "enc", "prop", "blocks", "dec", "euler", "total",
                  "contact", "terms", "MP GF/s");
    out << line;
    for (const auto& s : result.stages) {
      const double total = s.graph_build + s.world_edge_query + s.encode + s.propagate + s.blocks + s.decode + s.euler;
      std::snprintf(line, sizeof line,
                    "  %-3d %-*s %3lld %6.1f %6.1f %6.1f %6.1f %6.1f %6.1f %6.1f %6.1f %7.1f %7.1f %8.1f\n",
                    s.level, int(w), s.method.c_str(), static_cast<long long>(s.K), s.graph_build,
                    s.world_edge_query, s.encode, s.propagate, s.blocks, s.decode, s.euler, total,
                    s.contact_query, s.physics_terms, s.message_passing_gflops);
      out << line;
    }
    out << "  dense matmul (same threads, at start): " << fixed(result.matmul_gflops, 1) << " GFLOP/s\n";
    for (const auto& s : result.stages)
      if (s.with_body)
        out << "  Lv." << s.level << " " << s.method << ": message passing " << fixed(s.message_passing_gflops, 1)
            << " GFLOP/s = " << fixed(100.0 * s.message_passing_gflops / s.matmul_gflops, 0)
            << "% of the dense matmul's " << fixed(s.matmul_gflops, 1) << " GFLOP/s timed alongside\n";
  }

  // Speed-up over the reference solver (and Blender) at equal loss: the cheapest run that ran to
  // the end with a positive energy (stretch + bending + collision) not above the network's.
  // The total would compare gravity, which is ~1 J a frame for every method.
  auto equal_loss = [&](const std::string& family, const std::string& who, const std::string& budget) {
    const bool any = std::any_of(result.rows.begin(), result.rows.end(), [&](const BenchRow& r) { return r.family == family; });
    if (!any) return;
    out << "\nNetworks vs " << who << " at equal loss\n";
    for (int level : levels) {
      for (const auto& net : result.rows) {
        if (net.level != level || net.family != "network" || !std::isfinite(net.positive_loss)) continue;
        const BenchRow* best = cheapest_at_equal_loss(result.rows, net, family);
        const BenchRow* most = nullptr;
        for (const auto& ref : result.rows)
          if (ref.level == level && ref.family == family && (!most || ref.iterations > most->iterations)) most = &ref;
        if (!most) continue;
        out << "  Lv." << level << " " << net.method << ": ";
        if (best)
          out << best->method << " reaches its loss in " << fixed(best->latency_ms_median, 1) << " ms: "
              << fixed(best->latency_ms_median / net.latency_ms_median, 1) << "x the network's "
              << fixed(net.latency_ms_median, 1) << " ms\n";
        else
          out << "no " << budget << " reaches its loss (up to " << most->method << ", "
              << fixed(most->latency_ms_median, 1) << " ms = "
              << fixed(most->latency_ms_median / net.latency_ms_median, 1) << "x the network's "
              << fixed(net.latency_ms_median, 1) << " ms, positive energy " << fixed(most->positive_loss, 4)
              << " J against the network's " << fixed(net.positive_loss, 4) << " J)\n";
      }
    }
  };
  equal_loss("reference", "the reference solver (penalty contact)", "reference budget");
  equal_loss("reference_barrier", "the reference solver (intersection-free contact)", "reference budget");
  equal_loss("blender", "Blender's cloth", "Blender quality");
  if (levels.size() >= 2) {
    out << "\nLatency growth exponent in vertex count (least squares over levels, log-log)\n";
    for (const auto& m : methods) {
      const bool one_row_per_level =
          std::count_if(result.rows.begin(), result.rows.end(), [&](const BenchRow& r) { return r.method == m; }) ==
          std::ptrdiff_t(levels.size());
      if (!one_row_per_level) continue;  // fixed-K sweeps: several K per level
      const double e = latency_exponent(result.rows, m);
      if (std::isfinite(e)) out << "  " << m << ": " << fixed(e, 2) << "\n";
    }
  }
  return out.str();
}

}  // namespace pb4u

#include "pb4u/garment/clear_of_body.h"

#include <Eigen/Geometry>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <vector>

#include "pb4u/mesh/edges.h"
#include "pb4u/spatial/segments_through_surface.h"
#include "pb4u/spatial/signed_distance_to_surface.h"

namespace pb4u {
namespace {

// Points along an edge at which its depth in the body is sampled (the ends excluded).
constexpr int kDepthSamples = 15;

}  // namespace

BodyClearance clear_of_body(TriMesh& garment, const TriMesh& body, double clearance, int max_rounds) {
  BodyClearance out;
  Eigen::MatrixXd& V = garment.V;
  const Eigen::Index n = V.rows();
  const Eigen::MatrixXi edges = unique_edges(garment.F);
  const SurfaceQuery surface(body.V, body.F);
  const Eigen::MatrixXd start = V;
  std::vector<int> through = segments_through_surface(V, edges, body.V, body.F);
  out.edges_through_before = int(through.size());
  auto too_close = [&](const SurfaceProjection& p, Eigen::Index i) { return p.distance(i) < clearance * (1 - 1e-9); };
  for (int round = 0;; ++round) {
    const SurfaceProjection p = surface.project(V);
    Eigen::MatrixXd shift = Eigen::MatrixXd::Zero(n, 3);
    for (Eigen::Index i = 0; i < n; ++i)
      if (too_close(p, i)) shift.row(i) = p.closest.row(i) + clearance * p.outward.row(i) - V.row(i);
    if (!through.empty()) {
      const Eigen::Index m = Eigen::Index(through.size());
      Eigen::MatrixXd samples(m * kDepthSamples, 3);
      for (Eigen::Index k = 0; k < m; ++k)
        for (int j = 0; j < kDepthSamples; ++j) {
          const double t = (j + 1.0) / (kDepthSamples + 1);
          const int e = through[size_t(k)];
          samples.row(k * kDepthSamples + j) = (1 - t) * V.row(edges(e, 0)) + t * V.row(edges(e, 1));
        }
      const SurfaceProjection s = surface.project(samples);
      for (Eigen::Index k = 0; k < m; ++k) {
        Eigen::Index j;
        const double depth = s.distance.segment(k * kDepthSamples, kDepthSamples).minCoeff(&j);
        const Eigen::RowVector3d move = (clearance - depth) * s.outward.row(k * kDepthSamples + j);
        for (int end = 0; end < 2; ++end) {
          const int i = edges(through[size_t(k)], end);
          if (move.squaredNorm() > shift.row(i).squaredNorm()) shift.row(i) = move;
        }
      }
    }
    if (round == max_rounds || (through.empty() && shift.isZero(0))) {
      out.edges_through = int(through.size());
      for (Eigen::Index i = 0; i < n; ++i) out.vertices_inside += too_close(p, i) ? 1 : 0;
      break;
    }
    V += shift;
    through = segments_through_surface(V, edges, body.V, body.F);
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    const double d = (V.row(i) - start.row(i)).norm();
    out.moved += d > 0 ? 1 : 0;
    out.largest_move = std::max(out.largest_move, d);
  }
  if (out.moved > 0) {
    auto normal = [&](const Eigen::MatrixXd& X, Eigen::Index f) {
      const Eigen::Vector3d a = X.row(garment.F(f, 0)).transpose(), b = X.row(garment.F(f, 1)).transpose(),
                            c = X.row(garment.F(f, 2)).transpose();
      return Eigen::Vector3d((b - a).cross(c - a));
    };
    for (Eigen::Index f = 0; f < garment.F.rows(); ++f) out.folded_faces += normal(start, f).dot(normal(V, f)) < 0 ? 1 : 0;
  }
  return out;
}

BodyClearance clear_of_body_logged(TriMesh& garment, const TriMesh& body, double clearance, const std::string& label) {
  const BodyClearance cleared = clear_of_body(garment, body, clearance);
  if (cleared.moved > 0)
    spdlog::info("{}: {} edges through the body at rest; {} vertices moved out (at most {:.1f} mm) to {} mm clear", label,
                 cleared.edges_through_before, cleared.moved, 1e3 * cleared.largest_move, 1e3 * clearance);
  if (cleared.folded_faces > 0)
    spdlog::warn("{}: clearing the rest mesh of the body folded {} faces: the garment does not fit the body at its "
                 "bind pose (a limb through its walls); fit it round the body first for a clean rest shape",
                 label, cleared.folded_faces);
  if (!cleared.clear())
    spdlog::warn("{}: {} edges still through the body at rest and {} vertices within {} mm of it", label,
                 cleared.edges_through, cleared.vertices_inside, 1e3 * clearance);
  return cleared;
}

}  // namespace pb4u

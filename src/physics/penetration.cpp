#include "pb4u/physics/penetration.h"

#include <algorithm>

#include "pb4u/body/outer_faces.h"
#include "pb4u/spatial/signed_distance_to_surface.h"
#include "pb4u/spatial/winding_number.h"
#include "pb4u/util/error.h"

namespace pb4u {

PenetrationFigures garment_penetration(const Eigen::MatrixXd& garment, const Eigen::MatrixXd& body_V,
                                       const Eigen::MatrixXi& body_F) {
  if (garment.rows() == 0 || garment.cols() != 3) throw Error("penetration: the garment has no vertices");
  if (body_V.rows() == 0 || body_F.rows() == 0) throw Error("penetration: the body has no faces");
  if (!garment.allFinite()) throw Error("penetration: garment positions are not finite");
  // Only vertices in the body's bounding box can be inside; far ones would cost the exact
  // distance query many candidate faces for nothing.
  const Eigen::RowVector3d lo = body_V.colwise().minCoeff(), hi = body_V.colwise().maxCoeff();
  std::vector<Eigen::Index> boxed;
  for (Eigen::Index i = 0; i < garment.rows(); ++i)
    if ((garment.row(i).array() >= lo.array()).all() && (garment.row(i).array() <= hi.array()).all())
      boxed.push_back(i);
  PenetrationFigures out;
  const WindingNumbers body(body_V, body_F);
  const std::vector<char> covered = covered_faces(body_V, body_F, &body);
  out.body_self_crossing_faces = int(std::count(covered.begin(), covered.end(), char(1)));
  if (boxed.empty()) return out;
  Eigen::MatrixXd points(boxed.size(), 3);
  for (size_t k = 0; k < boxed.size(); ++k) points.row(k) = garment.row(boxed[k]);
  // Inside: wrapped by the body at least once, which also holds where one part of the body is
  // inside another (there the nearest face's side, which signed_distance_to_surface reads, can
  // say outside). Depth: the distance to the faces no other part covers.
  const Eigen::VectorXi wraps = body.at(points);
  std::vector<Eigen::Index> inside;
  for (Eigen::Index k = 0; k < wraps.size(); ++k)
    if (wraps(k) >= 1) inside.push_back(k);
  out.penetrating_fraction = double(inside.size()) / double(garment.rows());
  if (inside.empty()) return out;
  Eigen::MatrixXd deep(inside.size(), 3);
  for (size_t k = 0; k < inside.size(); ++k) deep.row(Eigen::Index(k)) = points.row(inside[k]);
  const Eigen::MatrixXi outer = outer_faces(body_F, covered);  // the faces counted above, left out
  const Eigen::VectorXd d = signed_distance_to_surface(deep, body_V, outer.rows() > 0 ? outer : body_F);
  out.max_penetration_mm = d.cwiseAbs().maxCoeff() * 1e3;
  return out;
}

PenetrationSummary summarize_penetration(const std::vector<PenetrationFigures>& frames) {
  if (frames.empty()) throw Error("penetration: no frame to summarise");
  // A frame is a one-frame summary.
  std::vector<PenetrationSummary> each;
  for (const auto& f : frames)
    each.push_back({f.penetrating_fraction, f.penetrating_fraction, f.max_penetration_mm, f.edges_through,
                    f.edges_through > 0 ? 1 : 0, 1, f.body_self_crossing_faces, f.body_self_crossing_faces > 0 ? 1 : 0});
  return summarize_penetration(each);
}

PenetrationSummary summarize_penetration(const std::vector<PenetrationSummary>& sequences) {
  if (sequences.empty()) throw Error("penetration: no sequence to summarise");
  PenetrationSummary s;
  for (const auto& q : sequences) {
    s.penetrating_fraction += q.penetrating_fraction / double(sequences.size());
    s.max_penetrating_fraction = std::max(s.max_penetrating_fraction, q.max_penetrating_fraction);
    s.max_penetration_mm = std::max(s.max_penetration_mm, q.max_penetration_mm);
    s.max_edges_through = std::max(s.max_edges_through, q.max_edges_through);
    s.frames_with_edges_through += q.frames_with_edges_through;
    s.frames += q.frames;
    s.max_body_self_crossing_faces = std::max(s.max_body_self_crossing_faces, q.max_body_self_crossing_faces);
    s.frames_with_body_self_crossing += q.frames_with_body_self_crossing;
  }
  return s;
}

}  // namespace pb4u

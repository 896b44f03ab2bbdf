#include "pb4u/physics/body_queries.h"

#include <atomic>
#include <limits>

#include "pb4u/spatial/point_kd_tree.h"
#include "pb4u/util/eigen_tensor.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace {

std::atomic<int64_t> g_trees_built{0};

PointKdTree make_body_tree(const Eigen::MatrixXd& points) {
  ++g_trees_built;
  return PointKdTree(points);
}

void check_points(const torch::Tensor& t, const char* what) {
  if (!t.defined() || t.dim() != 2 || t.size(1) != 3 || !t.is_floating_point())
    throw Error(std::string("body queries: ") + what + " must be (n, 3) floating point");
  // A NaN would silently match an arbitrary KD-tree leaf.
  if (!torch::isfinite(t).all().item<bool>())
    throw Error(std::string("body queries: ") + what + " are not finite");
}

// Face centroids and (unit, where the face is not degenerate) normals of V (nb, 3) over F.
void face_frames(const torch::Tensor& V, const torch::Tensor& F, double degenerate_area,
                 torch::Tensor* centroid, torch::Tensor* normal) {
  auto v0 = V.index_select(0, F.select(1, 0)), v1 = V.index_select(0, F.select(1, 1)),
       v2 = V.index_select(0, F.select(1, 2));
  *centroid = (v0 + v1 + v2) / 3.0;
  auto n = torch::cross(v1 - v0, v2 - v0, 1);
  *normal = n / n.norm(2, 1, true).clamp_min(degenerate_area);
}

}  // namespace

int64_t body_kd_trees_built() { return g_trees_built.load(); }

BodyContact query_body_contact(const torch::Tensor& x, const BodyFrame& body,
                               double contact_radius, double degenerate_area) {
  check_points(x, "garment positions");
  if (!body.defined()) throw Error("body queries: the scene has no body");
  check_points(body.vertices, "body vertices");
  check_points(body.next_vertices, "next body vertices");
  if (body.next_vertices.size(0) != body.vertices.size(0))
    throw Error("body queries: body vertex counts differ between t and t + dt");
  if (!body.faces.defined() || body.faces.dim() != 2 || body.faces.size(1) != 3 ||
      body.faces.size(0) == 0)
    throw Error("body queries: body faces must be (mb, 3) and non-empty");

  auto opts = x.options();
  torch::Tensor faces = body.faces.to(x.device(), torch::kInt64);
  if (faces.min().item<int64_t>() < 0 || faces.max().item<int64_t>() >= body.vertices.size(0))
    throw Error("body queries: body face index out of range");
  torch::Tensor V = body.vertices.detach().to(opts), Vn = body.next_vertices.detach().to(opts);
  torch::Tensor c_t, n_t, c_n, n_n;
  face_frames(V, faces, degenerate_area, &c_t, &n_t);
  face_frames(Vn, faces, degenerate_area, &c_n, &n_n);

  PointKdTree tree = make_body_tree(tensor_to_matrix(c_t));
  Eigen::VectorXi nearest;
  tree.nearest(tensor_to_matrix(x), &nearest);

  BodyContact c;
  c.face = index_vector_to_tensor(nearest, x.device());
  c.point = c_n.index_select(0, c.face);
  c.normal = n_n.index_select(0, c.face);
  c.motion = c.point - c_t.index_select(0, c.face);
  c.distance = ((x.detach() - c_t.index_select(0, c.face)) * n_t.index_select(0, c.face)).sum(1);
  c.in_contact = c.distance < contact_radius;
  c.degenerate_area = degenerate_area;
  return c;
}

BodyContact contact_on_faces(const BodyContact& contact, const torch::Tensor& x, const BodyFrame& body,
                             const std::vector<int64_t>& rows) {
  if (rows.empty()) throw Error("body queries: no body face to measure the contact against");
  const int64_t faces = body.faces.size(0);
  for (int64_t r : rows)
    if (r < 0 || r >= faces) throw Error("body queries: body face row out of range");
  const torch::Tensor kept = torch::tensor(rows, torch::kInt64).to(body.faces.device());
  BodyFrame some = body;
  some.faces = body.faces.index_select(0, kept);
  BodyContact c = query_body_contact(x, some, std::numeric_limits<double>::infinity(), contact.degenerate_area);
  c.face = kept.to(c.face.device()).index_select(0, c.face);
  c.in_contact = contact.in_contact;
  return c;
}

std::optional<BodyContact> body_contact_for(const FrameState& state, const PhysicsConfig& config) {
  if (!state.effects.needs_body()) return std::nullopt;
  if (!state.body.defined())
    throw Error("scene: effects collision/friction need a body, and the scene has none");
  return query_body_contact(state.x, state.body, config.friction.contact_radius,
                            config.degenerate_area);
}

torch::Tensor nearest_body_vertex(const torch::Tensor& x, const torch::Tensor& body_vertices,
                                  torch::Tensor* squared_distance) {
  check_points(x, "garment positions");
  check_points(body_vertices, "body vertices");
  if (body_vertices.size(0) == 0) throw Error("body queries: the body has no vertices");
  PointKdTree tree = make_body_tree(tensor_to_matrix(body_vertices));
  Eigen::VectorXi idx;
  Eigen::VectorXd d2;
  tree.nearest(tensor_to_matrix(x), &idx, &d2);
  if (squared_distance)
    *squared_distance = torch::from_blob(d2.data(), {d2.size()}, torch::kFloat64).to(x.options()).clone();
  return index_vector_to_tensor(idx, x.device());
}

}  // namespace pb4u

#pragma once
// Garment <-> body proximity, with nanoflann KD-trees (PointKdTree): O((n + nb) log nb).
// Built only for scenes whose effects need a body (SPEC 6): see body_contact_for().
#include <torch/torch.h>

#include <optional>
#include <vector>

#include "pb4u/physics/physics_config.h"
#include "pb4u/scene/frame_state.h"

namespace pb4u {

// Per garment vertex, the body face it is matched to for one step (SPEC 3.3): the face whose
// centroid is nearest at time t; its plane is taken at t + dt. Tensors in x's dtype / device.
struct BodyContact {
  torch::Tensor face;        // (n) int64: nearest body face (by centroid, at t)
  torch::Tensor point;       // (n, 3) m: that face's centroid at t + dt
  torch::Tensor normal;      // (n, 3) unit outward normal of that face at t + dt
  torch::Tensor motion;      // (n, 3) m: displacement of the centroid from t to t + dt
  torch::Tensor distance;    // (n) m: signed distance of x_t to the face's plane at t
  torch::Tensor in_contact;  // (n) bool: distance < contact radius (friction applies)
  // m^2: faces below it keep unnormalised normals; the query's (the default where built by hand).
  double degenerate_area = kDefaultDegenerateArea;
};

// x: (n, 3) m garment positions at t. body: vertices at t and t + dt, faces (outward).
// contact_radius in m; degenerate_area in m^2 (normals of smaller faces are left unnormalised).
BodyContact query_body_contact(const torch::Tensor& x, const BodyFrame& body,
                               double contact_radius, double degenerate_area);

// `contact` (query_body_contact's, of x over all of body's faces) measured again against the
// faces `rows` of the body alone: each vertex's nearest of them by centroid at t, its centroid,
// normal and motion at t + dt, with `contact`'s degenerate area. Whether a vertex is in contact
// (in_contact, for friction) stays `contact`'s. Throws pb4u::Error when rows is empty or out of
// range.
BodyContact contact_on_faces(const BodyContact& contact, const torch::Tensor& x, const BodyFrame& body,
                             const std::vector<int64_t>& rows);

// The step's contact when the scene's effects need a body, std::nullopt otherwise (no
// KD-tree is built then). Throws pb4u::Error when they need one and state.body is undefined.
std::optional<BodyContact> body_contact_for(const FrameState& state, const PhysicsConfig& config);

// x: (n, 3) m; body_vertices: (nb, 3) m. Index (n, int64) of the nearest body vertex of each
// garment vertex; its squared distance (m^2, x's dtype) into *squared_distance if given.
torch::Tensor nearest_body_vertex(const torch::Tensor& x, const torch::Tensor& body_vertices,
                                  torch::Tensor* squared_distance = nullptr);

// How many body KD-trees this process has built: lets tests show a body-less scene builds none.
int64_t body_kd_trees_built();

}  // namespace pb4u

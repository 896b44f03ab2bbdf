#include "pb4u/garment/garment_template.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "pb4u/body/forward_kinematics.h"
#include "pb4u/body/marching_tetrahedra.h"
#include "pb4u/garment/clip_mesh.h"
#include "pb4u/garment/skin_weight_transfer.h"
#include "pb4u/mesh/largest_component.h"
#include "pb4u/mesh/remesh.h"
#include "pb4u/util/error.h"

namespace pb4u {

const std::vector<std::string>& garment_template_names() {
  static const std::vector<std::string> names = {"tshirt", "tank_top", "long_sleeve",
                                                 "long_dress", "skirt"};
  return names;
}

namespace {

using ScalarField = std::function<double(const Eigen::Vector3d&)>;

TriMesh clip_with(const TriMesh& mesh, const ScalarField& g) {
  Eigen::VectorXd values(mesh.V.rows());
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) values[i] = g(mesh.V.row(i).transpose());
  return clip_mesh(mesh, values);
}

}  // namespace

TriMesh garment_template_surface(const std::string& name, const Body& body,
                                 const MannequinConfig& mannequin,
                                 const GarmentTemplateConfig& config) {
  const auto& names = garment_template_names();
  if (std::find(names.begin(), names.end(), name) == names.end())
    throw Error("garment template '" + name +
                "': unknown (tshirt, tank_top, long_sleeve, long_dress, skirt)");
  const Skeleton& s = body.skeleton;
  const HumanoidJoints h = find_humanoid_joints(s, body.name);
  double H = 0;
  const ImplicitBody solid = humanoid_implicit(s, h, body.bind, mannequin, &H);
  const Eigen::MatrixXd P = joint_positions(s, body.bind);
  auto at = [&](int j) -> Eigen::Vector3d { return P.row(j).transpose(); };

  const double root_y = P(h.root, 1), chest_y = P(h.chest(), 1);
  const double torso = chest_y - root_y;
  const double knee_y = 0.5 * (P(h.knee[0], 1) + P(h.knee[1], 1));
  const double thigh = (at(h.knee[0]) - at(h.thigh[0])).norm();
  const double shin = (at(h.ankle[0]) - at(h.knee[0])).norm();
  const bool skirt = name == "skirt", dress = name == "long_dress";
  const bool cone = skirt || dress;

  double hem_y = root_y + config.shirt_hem * torso;
  if (skirt) hem_y = knee_y + config.skirt_hem * thigh;
  if (dress) hem_y = knee_y + config.dress_hem * shin;
  const double cone_top = root_y + config.skirt_top * torso;
  const Eigen::Vector3d hips = 0.5 * (at(h.thigh[0]) + at(h.thigh[1]));
  auto cone_axes = [&](double y) {
    const double drop = cone_top - y;
    return Eigen::Vector2d(std::max(config.cone_half_width * H + config.flare_x * drop, 0.01),
                           std::max(config.cone_half_depth * H + config.flare_z * drop, 0.01));
  };
  // Negative inside a flared elliptic cone hanging from the waistband, capped at its top.
  auto cone_field = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector2d ax = cone_axes(p.y());
    const double dx = (p.x() - hips.x()) / ax[0], dz = (p.z() - hips.z()) / ax[1];
    const double side = (std::sqrt(dx * dx + dz * dz) - 1.0) * ax.minCoeff();
    return std::max(side, p.y() - cone_top);
  };

  // Grid over the garment's height range only.
  const double margin = 3 * config.cell_size + config.gap + solid.blend;
  Eigen::Matrix<double, 2, 3> box = solid.bounds();
  box(0, 1) = hem_y - margin;
  box(1, 1) = skirt ? cone_top + margin : P(h.head, 1);
  if (cone) {
    const Eigen::Vector2d ax = cone_axes(hem_y - margin);
    box(0, 0) = std::min(box(0, 0), hips.x() - ax[0]);
    box(1, 0) = std::max(box(1, 0), hips.x() + ax[0]);
    box(0, 2) = std::min(box(0, 2), hips.z() - ax[1]);
    box(1, 2) = std::max(box(1, 2), hips.z() + ax[1]);
  }
  const Grid grid = grid_around(box, config.cell_size, margin);
  Eigen::VectorXd values = sample_implicit(solid, grid, config.gap).array() - config.gap;
  if (cone) {
    for (int i = 0; i < grid.nx; ++i)
      for (int j = 0; j < grid.ny; ++j)
        for (int k = 0; k < grid.nz; ++k) {
          const Eigen::Index n = (Eigen::Index(i) * grid.ny + j) * grid.nz + k;
          values[n] = smooth_min(values[n], cone_field(grid.node(i, j, k)), config.cone_blend);
        }
  }
  TriMesh mesh = marching_tetrahedra(grid, values);

  mesh = clip_with(mesh, [&](const Eigen::Vector3d& p) { return p.y() - hem_y; });
  if (skirt) {
    mesh = clip_with(mesh, [&](const Eigen::Vector3d& p) { return cone_top - p.y(); });
  } else {
    const Eigen::Vector3d neck = at(h.chest());
    const double neck_y = chest_y + config.neck_cut_height * torso;
    const bool scoop = name == "tank_top" || dress;
    const double hole = (scoop ? config.scoop_neck_hole_radius : config.neck_hole_radius) * H;
    mesh = clip_with(mesh, [&](const Eigen::Vector3d& p) {
      const double radial = std::hypot(p.x() - neck.x(), p.z() - neck.z());
      return std::max(neck_y - p.y(), radial - hole);
    });
    const double fraction = name == "tshirt"        ? config.tshirt_sleeve
                            : name == "long_sleeve" ? config.long_sleeve
                                                    : config.sleeveless;
    for (int k = 0; k < 2; ++k) {
      const Eigen::Vector3d shoulder = at(h.upper_arm[k]);
      const Eigen::Vector3d axis = (at(h.elbow[k]) - shoulder).normalized();
      const double arm = (at(h.elbow[k]) - shoulder).norm() + (at(h.wrist[k]) - at(h.elbow[k])).norm();
      const double length = fraction * arm, radius = config.sleeve_cut_radius * H;
      mesh = clip_with(mesh, [&](const Eigen::Vector3d& p) {
        const Eigen::Vector3d v = p - shoulder;
        const double along = v.dot(axis);
        return std::max(length - along, (v - along * axis).norm() - radius);
      });
    }
  }
  mesh = largest_component(mesh);
  if (mesh.num_faces() == 0) throw Error("garment template '" + name + "': empty surface");
  return mesh;
}

Garment make_garment(const std::string& name, const TriMesh& surface, const Body& body,
                     int target_triangles, const SkinWeightOptions& skin) {
  Garment g;
  g.name = name;
  g.mesh = remesh_to_triangle_count(surface, target_triangles);
  g.weights = garment_skin_weights(g.mesh, body, skin);
  return g;
}

}  // namespace pb4u

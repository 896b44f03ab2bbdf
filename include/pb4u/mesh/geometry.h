#pragma once
// Per-element measures of a triangle mesh. V: n x 3 (metres), F: m x 3.
#include <Eigen/Core>

namespace pb4u {

// m face areas (m^2).
Eigen::VectorXd face_areas(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// m x 3 unit face normals (zero for degenerate faces).
Eigen::MatrixXd face_normals(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// n x 3 unit vertex normals, area-weighted average of incident face normals.
Eigen::MatrixXd vertex_normals(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// n lumped masses (kg): each face gives density * area / 3 to its vertices.
// density: area density in kg/m^2.
Eigen::VectorXd vertex_masses(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, double density);

// Lengths (m) of the E x 2 edges.
Eigen::VectorXd edge_lengths(const Eigen::MatrixXd& V, const Eigen::MatrixXi& E);

// Mean length (m) of the mesh's unique edges: the Lbar of SPEC 4.
double mean_edge_length(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// Per vertex, the mean length (m) of its incident unique edges (0 for isolated vertices):
// the numerator of the update scaling s_i.
Eigen::VectorXd vertex_mean_edge_length(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// Axis-aligned bounds: row 0 the minimum, row 1 the maximum corner.
Eigen::Matrix<double, 2, 3> bounding_box(const Eigen::MatrixXd& V);

// Count of faces with area below `min_area` (m^2) or a repeated vertex.
int count_degenerate_faces(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, double min_area);

}  // namespace pb4u

#pragma once
// The faces of a posed body that no other part of it covers. An animated body crosses itself
// (the quick mannequin's upper arms sink into its torso below the armpits, its forearms swing
// into its hips): the faces of one part inside another are not the body's surface, and how deep
// a point is inside the body is its distance to the outer faces alone (physics/penetration.h).
// A face counts as covered when a point 0.1 mm outside its centroid is inside the body (winding
// number >= 1, spatial/winding_number.h).
#include <Eigen/Core>

#include <vector>

namespace pb4u {

class WindingNumbers;

// Per face of the closed, outward-oriented body (V, F): 1 where another part covers it.
// `wraps`: the same surface's winding numbers when the caller has them (else built here).
std::vector<char> covered_faces(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                const WindingNumbers* wraps = nullptr);

// The rows of F that no other part covers, in F's order; F itself when none is covered.
Eigen::MatrixXi outer_faces(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const WindingNumbers* wraps = nullptr);
// The same from covered_faces(V, F) already computed (one flag per row of F).
Eigen::MatrixXi outer_faces(const Eigen::MatrixXi& F, const std::vector<char>& covered);

}  // namespace pb4u

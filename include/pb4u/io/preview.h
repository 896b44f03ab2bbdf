#pragma once
// preview.png: a contact sheet of a rollout, a few frames from the front and the side, the
// garment shaded so folds show, its vertices inside the body in red, the body in grey.
// Drawn by scripts/plot_preview.py (matplotlib) from OBJ files written to a temp folder.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace pb4u {

// The frames a sheet shows: `count` frames spread evenly over 0..num_frames-1, the first and
// the last included (fewer when the rollout is shorter).
std::vector<int> preview_frames(int num_frames, int count = 4);

// Writes `png` from the given frames (garment frames and, when body_faces is non-empty, body
// frames with the same indices). Returns false, with a warning, when Python or matplotlib is
// missing: a picture is never worth failing the command for.
bool write_preview(const std::string& png, const std::vector<int>& frames,
                   const std::vector<Eigen::MatrixXd>& garment, const Eigen::MatrixXi& garment_faces,
                   const std::vector<Eigen::MatrixXd>& body, const Eigen::MatrixXi& body_faces,
                   const std::string& title);

}  // namespace pb4u

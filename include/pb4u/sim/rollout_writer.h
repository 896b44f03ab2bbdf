#pragma once
// Everything `simulate` writes, frame by frame: garment (and body) meshes per frame as OBJ
// or PLY, a PC2 point cache per mesh, a USD cache of both meshes (scene.usda), one HDF5 with
// all frames (float64), and per-frame energies as CSV. Each file is written atomically; finish() can run after a failure and keeps every
// frame written so far.
#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

namespace pb4u {

struct RolloutOutputs {
  std::string mesh_format = "obj";  // obj | ply | none: one file per frame and mesh
  bool point_cache = true;          // garment.pc2 (+ body.pc2)
  bool usd_cache = true;            // scene.usda: prims /pb4u/Garment (+ /pb4u/Body)
  bool hdf5 = true;                 // rollout.h5
  bool energies_csv = true;         // energies.csv
  double fps = 30.0;                // frames per second of rollout.h5 and scene.usda
};

class RolloutWriter {
 public:
  // body_faces may be empty (no body in the scene). `out_dir` must exist.
  RolloutWriter(std::string out_dir, Eigen::MatrixXi garment_faces, Eigen::MatrixXi body_faces,
                RolloutOutputs outputs);

  // One frame: garment positions (n x 3, m), body positions (nb x 3, m; ignored without a
  // body) and the frame's energies (name, J) in a fixed order across frames.
  void add_frame(const Eigen::MatrixXd& garment, const Eigen::MatrixXd& body,
                 const std::vector<std::pair<std::string, double>>& energies);

  // The garment's rest shape and its positions one frame before frame 0: what a scorer needs
  // besides the frames (`pb4u score`). Written as garment_rest.<obj|ply> now (unless the
  // mesh format is none) and into rollout.h5 (garment/rest, garment/previous) by finish().
  void set_rest_and_previous(const Eigen::MatrixXd& rest, const Eigen::MatrixXd& previous);

  // Writes the point caches, the HDF5 and the CSV for the frames added so far. Returns the
  // list of files written (per-frame meshes included).
  std::vector<std::string> finish();

  int num_frames() const { return static_cast<int>(garment_frames_.size()); }
  const std::vector<Eigen::MatrixXd>& garment_frames() const { return garment_frames_; }
  const std::vector<Eigen::MatrixXd>& body_frames() const { return body_frames_; }

 private:
  std::string dir_;
  Eigen::MatrixXi garment_faces_, body_faces_;
  RolloutOutputs outputs_;
  std::vector<Eigen::MatrixXd> garment_frames_, body_frames_;
  Eigen::MatrixXd rest_, previous_;
  std::vector<std::string> energy_names_;
  std::vector<std::vector<double>> energies_;
  std::vector<std::string> written_;
};

// "<dir>/<stem>_0007.<ext>"
std::string frame_file(const std::string& dir, const std::string& stem, int frame, const std::string& ext);

}  // namespace pb4u

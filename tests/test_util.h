#pragma once
// Helpers shared by the test suites.
#include <string>

#include "pb4u/mesh/triangle_mesh.h"

namespace pb4u::test {

// The source tree (configs/, data/, scripts/).
inline const std::string kSource = PB4U_SOURCE_DIR;

// A fresh empty directory under the system temp dir, unique per call. Removed when the test
// process exits (kept with PB4U_KEEP_TEST_DIRS=1, to look at a failure's files).
std::string temp_dir(const std::string& tag);

// Writes `text` to `path` (overwriting).
void write_file(const std::string& path, const std::string& text);
std::string read_file(const std::string& path);

struct CommandResult {
  int exit_code = -1;
  std::string out, err;
};
// Runs the pb4u binary with `args` (shell-quoted by the caller) and captures its streams.
CommandResult run_pb4u(const std::string& args);

// configs/data/tiny.yaml generated with the real `pb4u generate`, once per test process;
// returns the dataset file.
const std::string& tiny_dataset();
// configs/data/hard.yaml likewise (seconds): the quick dataset's mannequin and its t-shirt at
// the training resolution, for the hard cases with a body.
const std::string& hard_dataset();

// An n x n grid of unit squares split into 2 n^2 triangles, in the xz plane at y = 0.
TriMesh grid_mesh(int n, double size = 1.0);

// A res_x x res_y cloth hanging in the xy plane (top row at y = 1 m, rows dy apart, odd rows
// shifted by dx / 2, so every edge is at least dx / 2 long), faces oriented +z. Row
// `thin_row`'s strip (between it and the next row) is squeezed to height `thin_height` (m):
// 1e-8 makes sliver triangles of area ~ dx * 1e-8 / 2, 0 zero-area ones. thin_row < 0: none.
TriMesh lattice_cloth(int res_x, int res_y, double dx, int thin_row = -1, double thin_height = 0.0);

// The closed box [lo, hi] as 12 outward triangles (two per side).
TriMesh box_mesh(const Eigen::RowVector3d& lo, const Eigen::RowVector3d& hi);
// Two meshes as one (b's indices shifted): a surface made of parts that may overlap.
TriMesh joined(const TriMesh& a, const TriMesh& b);

}  // namespace pb4u::test

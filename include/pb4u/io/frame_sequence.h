#pragma once
// Cloth (or body) frames from any tool, in the mesh's own vertex order: a PC2 point cache,
// a pb4u rollout.h5, a USD text cache, or a numbered OBJ/PLY sequence. What `pb4u score` reads.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "pb4u/mesh/triangle_mesh.h"

namespace pb4u {

// A mesh exactly as the file lists it: vertex i is the file's i-th vertex (no welding, no
// reordering, unlike read_mesh), so it lines up with a point cache of the same mesh. OBJ
// (v / f lines; polygons fanned into triangles) and PLY (ascii, binary little/big endian).
// Throws pb4u::Error naming `path` on a missing, unreadable or malformed file.
TriMesh read_mesh_in_file_order(const std::string& path);

struct FrameSequence {
  std::vector<Eigen::MatrixXd> frames;  // T matrices of n x 3 positions, m
  Eigen::MatrixXi faces;                // m x 3 when the source has faces (OBJ/PLY, rollout.h5)
  // rollout.h5 only (empty otherwise): the rest shape and the frame before frame 0.
  Eigen::MatrixXd rest, previous;
};

// `source` is one of:
//  - "<file>.pc2": a Point Cache 2 file;
//  - "<file>.h5": a rollout written by `pb4u simulate` (`group`: "garment" or "body");
//  - "<file>.usda": a USD text cache (simulate's scene.usda, or another tool's): the Mesh prim
//    named like `group` ("garment" reads /pb4u/Garment; case is ignored; "garment" also reads
//    the only Mesh of a file that has one); its time samples are the frames, with its faces;
//  - a numbered mesh sequence: a printf pattern ("out/garment_%04d.obj") or a glob with one
//    '*' ("out/garment_*.obj"); frames in numeric order from the first file found.
// Every frame must have the same vertex count. Throws pb4u::Error naming the file and the frame.
FrameSequence read_frame_sequence(const std::string& source, const std::string& group = "garment");

}  // namespace pb4u

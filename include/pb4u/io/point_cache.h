#pragma once
// PC2 point caches (the Maya/Max/Blender "Point Cache 2" format): per-frame vertex positions
// of a fixed mesh. Blender: add a Mesh Cache modifier to the OBJ of frame 0, pick the .pc2.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace pb4u {

// frames: T matrices of n x 3 positions (m), all with the same n. Layout: char[12]
// "POINTCACHE2\0", int32 version 1, int32 n, float32 start frame, float32 sample rate
// (frames per sample, 1), int32 T, then T * n * 3 float32, little-endian. Written atomically.
void write_pc2(const std::string& path, const std::vector<Eigen::MatrixXd>& frames,
               double start_frame = 0.0);

// Reads a PC2 file back (for tests and `inspect`). Throws pb4u::Error naming the file if it
// is not a valid PC2 or is truncated.
std::vector<Eigen::MatrixXd> read_pc2(const std::string& path);

}  // namespace pb4u

#pragma once
// BVH motion capture files (CMU-style: ROOT with 6 channels, joints with 3 rotation channels
// in any order, degrees; offsets in the file's unit).
#include <string>

#include "pb4u/body/skeleton.h"

namespace pb4u {

struct BvhFile {
  Skeleton skeleton;  // End Sites are not joints
  Motion motion;      // at the file's frame rate
  double source_fps = 0.0;
  int source_frames = 0;
};

// Parses BVH text. `scale` multiplies offsets and root positions (e.g. 0.01 for centimetres).
// Throws pb4u::Error "<name>: line N: <reason>" on malformed input.
BvhFile parse_bvh(const std::string& text, const std::string& name, double scale = 1.0);

// Reads a BVH file and resamples its motion to `fps` (0 keeps the file's rate).
BvhFile read_bvh(const std::string& path, double fps = 30.0, double scale = 1.0);

}  // namespace pb4u

#pragma once
// The HDF5 training / evaluation dataset (schema in docs/data.md): bodies with skeletons and
// bind poses, garments per body at every resolution level, motions with a train/test split.
#include <ostream>
#include <string>
#include <vector>

#include "pb4u/body/body.h"
#include "pb4u/garment/garment.h"

namespace pb4u {

// One garment at every level (levels[k] has about level_triangles[k] triangles).
struct GarmentLevels {
  std::string name;
  std::vector<Garment> levels;
};

struct BodyRecord {
  Body body;
  std::vector<GarmentLevels> garments;
};

struct MotionRecord {
  std::string name;
  std::string body;    // the BodyRecord whose skeleton it drives
  std::string source;  // "procedural:<kind>" or the BVH path
  std::string split;   // "train", "test" or "heldout" (never trained on, outside the training ranges)
  Motion motion;
};

struct Dataset {
  std::vector<int> level_triangles;  // target triangles per level
  double density = 0.20022;          // kg/m^2, the area density the stored masses use
  std::vector<BodyRecord> bodies;
  std::vector<MotionRecord> motions;
  std::string config_yaml;  // the effective generate config

  const BodyRecord* find_body(const std::string& name) const;
};

// Writes atomically (temporary file renamed into place). Throws pb4u::Error naming `path`.
void write_dataset(const std::string& path, const Dataset& dataset);

// Reads and validates the whole file. A missing, truncated or corrupt file, or one that is
// not a pb4u dataset, gives a one-line pb4u::Error naming `path`.
Dataset read_dataset(const std::string& path);

// What `pb4u inspect` prints for a dataset.
void print_dataset_summary(std::ostream& out, const Dataset& dataset);

}  // namespace pb4u

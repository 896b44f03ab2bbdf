#include "pb4u/train/training_data.h"

#include <algorithm>
#include <cmath>

#include "pb4u/data/dataset.h"
#include "pb4u/util/error.h"

namespace pb4u {

TrainingData load_training_data(const TrainDataConfig& config) {
  Dataset dataset = read_dataset(config.dataset);
  TrainingData data;
  const int num_levels = static_cast<int>(dataset.level_triangles.size());
  for (int level : config.levels)
    if (level < 1 || level > num_levels)
      throw Error(config.dataset + ": data.levels has level " + std::to_string(level) +
                  " but the dataset has levels 1.." + std::to_string(num_levels));
  for (double speedup : config.speedups)
    if (!(speedup > 0) || !std::isfinite(speedup))
      throw Error("data.speedups: " + std::to_string(speedup) + " is not a positive speed-up");
  auto wanted = [&](const std::string& name) {
    return config.garments.empty() ||
           std::find(config.garments.begin(), config.garments.end(), name) != config.garments.end();
  };
  for (auto& record : dataset.bodies) {
    const int body_index = static_cast<int>(data.bodies.size());
    const size_t motions_before = data.motions.size();
    for (auto& m : dataset.motions)
      if (m.body == record.body.name && m.split == "train") {
        data.motions.push_back(m.motion);
        data.motion_body.push_back(body_index);
        for (double speedup : config.speedups) {
          // Played `speedup` times faster: sampled at fps / speedup, stepped at fps.
          Motion fast = resample_motion(m.motion, m.motion.fps / speedup);
          fast.fps = m.motion.fps;
          if (fast.num_frames() < 3) continue;  // too short to start a sample on
          data.motions.push_back(std::move(fast));
          data.motion_body.push_back(body_index);
        }
      }
    if (data.motions.size() == motions_before) continue;  // a body nothing moves: skip it
    for (auto& g : record.garments) {
      if (!wanted(g.name)) continue;
      for (int level : config.levels) {
        data.garments.push_back(g.levels[level - 1]);
        data.garment_body.push_back(body_index);
      }
    }
    data.bodies.push_back(std::move(record.body));
  }
  for (const auto& name : config.garments) {
    bool found = false;
    for (const auto& record : dataset.bodies)
      for (const auto& g : record.garments) found |= g.name == name;
    if (!found) throw Error(config.dataset + ": data.garments names '" + name + "', which the dataset does not have");
  }
  return data;
}

}  // namespace pb4u

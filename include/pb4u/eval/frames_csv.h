#pragma once
// Every frame of one evaluated rollout as CSV (`evaluate --frames-dir`): the figures a scene's
// energies.csv has, for the sequences evaluate rolls out, whose summaries keep only means and
// largest frames.
#include <string>
#include <vector>

#include "pb4u/rollout/rollout.h"

namespace pb4u {

// One row per measured frame (1..): each energy term (J), total, positive (stretch + bending +
// collision), residual_mm (nan where not measured), where frames were sampled for their
// minimum (minimum_every) distance_to_minimum_mm and energy_gap_j (nan on the others), and, when
// the rollout had a body,
// penetrating_fraction, max_penetration_mm, edges_through_body and body_self_crossing_faces
// (the body's faces inside another part of it: > 0 where it crosses itself); with `contact` (one per
// frame, the barrier solve's account), also contact_excluded, caught_by_body and body_lag_mm,
// as a scene's energies.csv has them. Written atomically, the folders made; throws pb4u::Error
// naming the file when it cannot be written.
void write_frames_csv(const std::string& path, const RolloutResult& r,
                      const std::vector<ContactStepLog>* contact = nullptr);

// A file name from free text (a method's name): letters, digits, '.' and '-' kept, every other
// run of characters one '_', none at either end.
std::string file_name_from(const std::string& text);

}  // namespace pb4u

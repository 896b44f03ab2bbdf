#pragma once
// The hood baseline's block schedule (model/hood_block.h); no torch here, so configs can use it.
#include <string>
#include <vector>

namespace pb4u {

// HOOD's own (configs/postcvpr.yaml of its public code): f,c0 x3, c0,c1 x3, c1 x3, c0,c1 x3, f,c0 x3.
constexpr const char* kHoodSchedule =
    "f,c0|f,c0|f,c0|c0,c1|c0,c1|c0,c1|c1|c1|c1|c0,c1|c0,c1|c0,c1|f,c0|f,c0|f,c0";
// ContourCraft's stage 1 (configs/ccraft_train/stage1.yaml): 15 flat blocks on f and c3.
constexpr const char* kContourCraftSchedule =
    "f,c3|f,c3|f,c3|f,c3|f,c3|f,c3|f,c3|f,c3|f,c3|f,c3|f,c3|f,c3|f,c3|f,c3|f,c3";

// The blocks' edge sets from a schedule "f,c0|f,c0|c0,c1|c1|...": one entry per block, '|'
// between blocks, ',' between sets; a "d:" or "u:" before an entry (HOOD's own marks for a
// change of level) is accepted and ignored, since the sets say it. Set s is 0 for f, L + 1 for
// cL. Throws pb4u::Error naming `where` on an empty entry or an unknown set or level.
std::vector<std::vector<int>> parse_hood_schedule(const std::string& schedule, int coarse_levels,
                                                  const std::string& where = "model.hood_schedule");

}  // namespace pb4u

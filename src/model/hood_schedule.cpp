#include "pb4u/model/hood_schedule.h"

#include <algorithm>
#include <cctype>
#include <sstream>

#include "pb4u/util/error.h"

namespace pb4u {

std::vector<std::vector<int>> parse_hood_schedule(const std::string& schedule, int coarse_levels,
                                                  const std::string& where) {
  std::vector<std::vector<int>> blocks;
  std::stringstream entries(schedule);
  std::string entry;
  while (std::getline(entries, entry, '|')) {
    if (entry.rfind("d:", 0) == 0 || entry.rfind("u:", 0) == 0) entry = entry.substr(2);
    std::vector<int> sets;
    std::stringstream names(entry);
    std::string name;
    while (std::getline(names, name, ',')) {
      int set = -1;
      if (name == "f") {
        set = 0;
      } else if (name.size() >= 2 && name.size() <= 4 && name[0] == 'c' &&
                 std::all_of(name.begin() + 1, name.end(), [](unsigned char c) { return std::isdigit(c) != 0; })) {
        const int level = std::stoi(name.substr(1));
        if (level < coarse_levels) set = level + 1;
      }
      if (set < 0)
        throw Error(where + ": block " + std::to_string(blocks.size() + 1) + " names '" + name +
                    "' (use f or c0..c" + std::to_string(coarse_levels - 1) + ")");
      if (std::find(sets.begin(), sets.end(), set) == sets.end()) sets.push_back(set);
    }
    if (sets.empty()) throw Error(where + ": block " + std::to_string(blocks.size() + 1) + " has no edge set");
    blocks.push_back(sets);
  }
  if (blocks.empty()) throw Error(where + ": no blocks");
  return blocks;
}

}  // namespace pb4u

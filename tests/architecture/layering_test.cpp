// Stages only look down: a file under src/<stage>/ or include/pb4u/<stage>/ includes pb4u
// headers of its own stage or of stages below it, in the order docs/architecture.md declares
// (its line "util < mesh < ... < cli"; stages joined by "=" are peers and include neither
// way). A stage folder the order does not name fails too, so a new stage must be placed.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "test_util.h"

namespace pb4u {
namespace {
namespace fs = std::filesystem;

// Rank of each stage: "a < b = c < d" gives a 0, b 1, c 1, d 2.
std::map<std::string, int> parse_stage_order(const std::string& line) {
  std::map<std::string, int> rank;
  std::stringstream in(line);
  std::string token;
  int level = 0;
  while (in >> token) {
    if (token == "<") {
      ++level;
    } else if (token != "=") {
      rank[token] = level;
    }
  }
  return rank;
}

// The first line of architecture.md that starts with "util <".
std::string stage_order_line(const std::string& architecture_md) {
  std::ifstream in(architecture_md);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("util <", 0) == 0) return line;
  return "";
}

// Every breach of the order under root/src and root/include/pb4u, one line each
// ("src/eval/x.cpp:3: eval includes sim/scene.h").
std::vector<std::string> layering_breaches(const std::string& root,
                                           const std::map<std::string, int>& rank) {
  static const std::regex include_line(R"(^\s*#\s*include\s*"pb4u/([a-z_0-9]+)/[^"]+")");
  std::vector<std::string> breaches;
  for (const std::string top : {"src", "include/pb4u"}) {
    const fs::path base = fs::path(root) / top;
    if (!fs::exists(base)) continue;
    for (const auto& stage_dir : fs::directory_iterator(base)) {
      if (!stage_dir.is_directory()) continue;
      const std::string stage = stage_dir.path().filename().string();
      const auto own = rank.find(stage);
      if (own == rank.end()) {
        breaches.push_back(top + "/" + stage + ": a stage the order does not name");
        continue;
      }
      for (const auto& entry : fs::recursive_directory_iterator(stage_dir.path())) {
        if (!entry.is_regular_file()) continue;
        std::ifstream in(entry.path());
        std::string line;
        std::smatch m;
        for (int number = 1; std::getline(in, line); ++number) {
          if (!std::regex_search(line, m, include_line)) continue;
          const std::string target = m[1];
          if (target == stage) continue;
          const auto other = rank.find(target);
          if (other == rank.end() || other->second >= own->second)
            breaches.push_back(fs::relative(entry.path(), root).string() + ":" +
                               std::to_string(number) + ": " + stage + " includes " +
                               line.substr(line.find("pb4u/") + 5));
        }
      }
    }
  }
  return breaches;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& l : lines) out += l + "\n";
  return out;
}

TEST(Layering, TheOrderParsesWithPeers) {
  const auto rank = parse_stage_order("util < mesh < sim = train = eval < cli");
  ASSERT_EQ(rank.size(), 6u);
  EXPECT_EQ(rank.at("util"), 0);
  EXPECT_EQ(rank.at("mesh"), 1);
  EXPECT_EQ(rank.at("sim"), 2);
  EXPECT_EQ(rank.at("eval"), 2);
  EXPECT_EQ(rank.at("cli"), 3);
}

TEST(Layering, AnUpwardOrPeerIncludeIsFound) {
  const std::string root = test::temp_dir("layering");
  fs::create_directories(root + "/src/mesh");
  fs::create_directories(root + "/src/sim");
  fs::create_directories(root + "/include/pb4u/odd");
  test::write_file(root + "/src/mesh/a.cpp",
                   "#include \"pb4u/mesh/a.h\"\n#include \"pb4u/util/error.h\"\n"
                   "  #  include \"pb4u/eval/rollout.h\"\n");
  test::write_file(root + "/src/sim/b.cpp", "#include \"pb4u/eval/x.h\"\n#include \"pb4u/mesh/a.h\"\n");
  const auto breaches = layering_breaches(root, parse_stage_order("util < mesh < sim = eval"));
  ASSERT_EQ(breaches.size(), 3u) << joined(breaches);
  const std::string all = joined(breaches);
  EXPECT_NE(all.find("src/mesh/a.cpp:3: mesh includes eval/rollout.h"), std::string::npos) << all;
  EXPECT_NE(all.find("src/sim/b.cpp:1: sim includes eval/x.h"), std::string::npos) << all;
  EXPECT_NE(all.find("include/pb4u/odd: a stage the order does not name"), std::string::npos) << all;
}

TEST(Layering, NoStageIncludesAStageAboveIt) {
  const std::string line = stage_order_line(test::kSource + "/docs/architecture.md");
  ASSERT_FALSE(line.empty()) << "docs/architecture.md has no line starting \"util <\"";
  const auto rank = parse_stage_order(line);
  EXPECT_GE(rank.size(), 10u) << line;
  const auto breaches = layering_breaches(test::kSource, rank);
  EXPECT_TRUE(breaches.empty()) << breaches.size() << " upward includes:\n" << joined(breaches);
}

}  // namespace
}  // namespace pb4u

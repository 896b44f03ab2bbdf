// scripts/rank_table.py (the table of scripts/rank_models.sh) on probe results written by hand:
// each run's mean with its min-max spread, the geometric-mean score, and a run whose rollout
// stopped early marked diverged and ranked last.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "test_util.h"

namespace pb4u {
namespace {
namespace fs = std::filesystem;

void write(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

std::string method(double e, bool diverged = false) {
  const std::string v = std::to_string(e / 2);
  return "{\"m\": {\"stretch\": " + v + ", \"bending\": 0, \"collision\": " + v +
         ", \"max_penetrating_fraction\": 0.01, \"diverged\": " + (diverged ? "true" : "false") + "}}";
}

// One member whose every probe has positive energy e per frame; its walk rolled `walk_rows`
// frames of the 2 asked for; its skirt diverged or not.
void write_member(const fs::path& dir, double e, int walk_rows = 2, bool skirt_diverged = false) {
  write(dir / "step.json", "{\"levels\": [{\"level\": 1, \"methods\": " + method(e) + "}]}");
  write(dir / "unseen.json", "{\"levels\": [{\"level\": 1, \"methods\": " + method(e) +
                                 "}, {\"level\": 5, \"methods\": " + method(e) + "}]}");
  write(dir / "skirt.json", "{\"levels\": [{\"level\": 1, \"methods\": " + method(e, skirt_diverged) + "}]}");
  const std::string half = std::to_string(e / 2);
  std::string walk = "frame,stretch,bending,collision,penetrating_fraction\n0,nan,nan,nan,nan\n";
  for (int f = 1; f <= walk_rows; ++f) walk += std::to_string(f) + "," + half + ",0," + half + ",0.02\n";
  write(dir / "walk" / "energies.csv", walk);
  write(dir / "walk" / "requested_frames", "2\n");
  write(dir / "hang" / "energies.csv", "frame,stretch,bending\n0,nan,nan\n1," + std::to_string(e) + ",0\n");
  write(dir / "hang" / "requested_frames", "1\n");
}

TEST(RankTable, MeansSpreadsScoresAndDivergence) {
  if (std::system("python3 -c 'import json, csv' 2>/dev/null") != 0) GTEST_SKIP() << "no python3";
  const fs::path root = test::temp_dir("rank_table");
  write_member(root / "good1", 0.2);
  write_member(root / "good2", 0.4);
  write_member(root / "bad1", 0.1, /*walk_rows=*/1);  // stopped a frame early
  write_member(root / "slip1", 0.1, 2, /*skirt_diverged=*/true);
  const std::string out = (root / "table.md").string();
  const std::string cmd = "python3 " + test::kSource + "/scripts/rank_table.py good:1:alone:" +
                          (root / "good1").string() + " good:2:alone:" + (root / "good2").string() +
                          " bad:1:alone:" + (root / "bad1").string() + " slip:1:alone:" +
                          (root / "slip1").string() + " --json " +
                          (root / "rank.json").string() + " > " + out;
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::ifstream in(out);
  std::string table((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto good = table.find("| good | network alone | 2 |"), bad = table.find("| bad | network alone | 1 |");
  ASSERT_NE(good, std::string::npos) << table;
  ASSERT_NE(bad, std::string::npos) << table;
  EXPECT_LT(good, bad) << "the diverged run ranks last";
  const std::string good_row = table.substr(good, table.find('\n', good) - good);
  const std::string bad_row = table.substr(bad, table.find('\n', bad) - bad);
  const auto slip = table.find("| slip | network alone | 1 |");
  ASSERT_NE(slip, std::string::npos) << table;
  EXPECT_LT(good, slip) << "a run whose skirt diverged ranks below one that did not";
  const std::string slip_row = table.substr(slip, table.find('\n', slip) - slip);
  EXPECT_NE(slip_row.find("| diverged | skirt |"), std::string::npos) << slip_row;
  // Every probe's energy (the skirt's too) is 0.2 in one member and 0.4 in the other: mean 0.3, spread 0.2-0.4,
  // and so is the geometric-mean score.
  EXPECT_NE(good_row.find("| 0.3000 (0.2000-0.4000) | none |"), std::string::npos) << good_row;
  EXPECT_NE(good_row.find("| 2.00 (2.00-2.00) |"), std::string::npos) << good_row;  // inside max %
  EXPECT_NE(bad_row.find("| diverged | walk |"), std::string::npos) << bad_row;
  EXPECT_TRUE(fs::exists(root / "rank.json"));
}

}  // namespace
}  // namespace pb4u

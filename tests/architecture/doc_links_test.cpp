// Every relative link in README.md and docs/ (the experiment log included) reaches its file,
// and every #anchor a heading of that file, as GitHub renders them: the pages cite one another
// by section, and a section renamed or moved must not leave a reader on a dead link. Links in
// code (fenced blocks, `spans`) and to the web are not checked.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "test_util.h"

namespace pb4u {
namespace {
namespace fs = std::filesystem;

// GitHub's anchor for a heading's text: lower case, spaces to hyphens, and every character
// that is not a letter, digit, hyphen, underscore or space dropped.
std::string heading_anchor(const std::string& text) {
  std::string out;
  for (unsigned char c : text) {
    if (std::isalnum(c) || c == '-' || c == '_')
      out += static_cast<char>(std::tolower(c));
    else if (c == ' ')
      out += '-';
    else if (c >= 0x80)
      out += static_cast<char>(c);  // letters outside ASCII stay, as GitHub keeps them
  }
  return out;
}

// A markdown file's lines outside fenced code blocks, with `code spans` blanked out.
std::vector<std::string> prose_lines(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  std::string line;
  bool fenced = false;
  while (std::getline(in, line)) {
    if (line.rfind("```", 0) == 0) {
      fenced = !fenced;
      continue;
    }
    if (fenced) continue;
    lines.push_back(std::regex_replace(line, std::regex("`[^`]*`"), "``"));
  }
  return lines;
}

// The anchors of a file's headings; a repeated heading gets -1, -2, ... as GitHub numbers them.
std::set<std::string> anchors_of(const fs::path& file) {
  std::set<std::string> anchors;
  std::map<std::string, int> seen;
  const std::regex heading(R"(^#{1,6}\s+(.*?)\s*$)");
  std::ifstream in(file);
  std::string line;
  bool fenced = false;
  while (std::getline(in, line)) {
    if (line.rfind("```", 0) == 0) fenced = !fenced;
    std::smatch m;
    if (fenced || !std::regex_match(line, m, heading)) continue;
    const std::string base = heading_anchor(m[1].str());
    const int n = seen[base]++;
    anchors.insert(n == 0 ? base : base + "-" + std::to_string(n));
  }
  return anchors;
}

std::vector<fs::path> pages() {
  std::vector<fs::path> files = {fs::path(test::kSource) / "README.md"};
  for (const auto& entry : fs::recursive_directory_iterator(fs::path(test::kSource) / "docs"))
    if (entry.is_regular_file() && entry.path().extension() == ".md") files.push_back(entry.path());
  return files;
}

// "page: link (why)" for each link of `page` that does not resolve.
std::vector<std::string> dead_links(const fs::path& page, std::map<fs::path, std::set<std::string>>& anchor_cache) {
  std::vector<std::string> dead;
  const std::regex link(R"(\]\(([^)\s]+)\))");
  for (const std::string& line : prose_lines(page)) {
    for (auto it = std::sregex_iterator(line.begin(), line.end(), link); it != std::sregex_iterator(); ++it) {
      const std::string target = (*it)[1].str();
      if (target.rfind("http://", 0) == 0 || target.rfind("https://", 0) == 0 || target.rfind("mailto:", 0) == 0)
        continue;
      const size_t hash = target.find('#');
      const std::string path = target.substr(0, hash);
      const std::string anchor = hash == std::string::npos ? "" : target.substr(hash + 1);
      const fs::path file = path.empty() ? page : (page.parent_path() / path).lexically_normal();
      const std::string where = fs::relative(page, test::kSource).string() + ": " + target;
      if (!fs::exists(file)) {
        dead.push_back(where + " (no such file)");
        continue;
      }
      if (anchor.empty() || file.extension() != ".md") continue;
      auto found = anchor_cache.find(file);
      if (found == anchor_cache.end()) found = anchor_cache.emplace(file, anchors_of(file)).first;
      if (!found->second.count(anchor)) dead.push_back(where + " (no such section)");
    }
  }
  return dead;
}

TEST(DocLinks, HeadingAnchorsAreGitHubs) {
  EXPECT_EQ(heading_anchor("Refining the network's step (`--refine N`)"), "refining-the-networks-step---refine-n");
  EXPECT_EQ(heading_anchor("Switches, off by default"), "switches-off-by-default");
  EXPECT_EQ(heading_anchor("The finest level (Lv.5)"), "the-finest-level-lv5");
  EXPECT_EQ(heading_anchor("CUDA and data-parallel scale (issue 10)"), "cuda-and-data-parallel-scale-issue-10");
}

TEST(DocLinks, EveryRelativeLinkReachesItsFileAndSection) {
  std::map<fs::path, std::set<std::string>> anchor_cache;
  std::vector<std::string> dead;
  int checked_pages = 0;
  for (const fs::path& page : pages()) {
    ++checked_pages;
    for (std::string& d : dead_links(page, anchor_cache)) dead.push_back(std::move(d));
  }
  EXPECT_GT(checked_pages, 10);
  std::ostringstream list;
  for (const std::string& d : dead) list << "\n  " << d;
  EXPECT_TRUE(dead.empty()) << dead.size() << " dead link(s):" << list.str();
}

}  // namespace
}  // namespace pb4u

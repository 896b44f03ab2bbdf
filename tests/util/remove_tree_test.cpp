// remove_tree (std::filesystem::remove_all without the symbol libtorch re-exports): a nested
// tree goes, links are removed but never followed, a missing path is no error.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "pb4u/util/error.h"
#include "pb4u/util/remove_tree.h"
#include "test_util.h"

namespace pb4u {
namespace {
namespace fs = std::filesystem;

TEST(RemoveTree, NestedTreeGoesLinksAreNotFollowed) {
  const std::string base = test::temp_dir("remove_tree");
  const std::string outside = base + "/outside", tree = base + "/tree";
  fs::create_directories(outside);
  test::write_file(outside + "/keep.txt", "kept");
  fs::create_directories(tree + "/a/b/c");
  fs::create_directories(tree + "/empty");
  test::write_file(tree + "/top.txt", "1");
  test::write_file(tree + "/a/b/c/deep.txt", "2");
  ASSERT_EQ(::symlink(outside.c_str(), (tree + "/a/link_to_outside").c_str()), 0);
  ASSERT_EQ(::symlink((tree + "/nowhere").c_str(), (tree + "/dangling").c_str()), 0);
  // tree, a, b, c, empty, 2 files, 2 links
  EXPECT_EQ(remove_tree(tree), 9u);
  EXPECT_FALSE(fs::exists(fs::symlink_status(tree)));
  EXPECT_EQ(test::read_file(outside + "/keep.txt"), "kept");  // the link went, not its target
  EXPECT_EQ(remove_tree(tree), 0u);                          // already gone: no error
  test::write_file(base + "/file", "x");
  EXPECT_EQ(remove_tree(base + "/file"), 1u);
  EXPECT_FALSE(fs::exists(base + "/file"));
  EXPECT_EQ(remove_tree(base), 3u);  // base, outside/ and keep.txt
}

TEST(RemoveTree, APathThroughAFileIsAnErrorNamingIt) {
  const std::string base = test::temp_dir("remove_tree_err");
  test::write_file(base + "/file", "x");
  try {
    remove_tree(base + "/file/below");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(base + "/file/below"), std::string::npos) << e.what();
  }
  remove_tree(base);
}

// A call of std::filesystem::remove_all compiles and passes here and crashes only in a build
// against PyTorch's LibTorch (one did: tests/install, found on a GPU machine). So no source or
// test file may call it.
TEST(RemoveTree, NoSourceOrTestCallsRemoveAll) {
  const std::regex call(R"((fs|filesystem)::remove_all\s*\()");
  int files = 0;
  for (const char* dir : {"src", "include", "tests"})
    for (const auto& entry : fs::recursive_directory_iterator(test::kSource + "/" + dir)) {
      const std::string ext = entry.path().extension().string();
      if (!entry.is_regular_file() || (ext != ".cpp" && ext != ".h")) continue;
      std::ifstream in(entry.path());
      std::stringstream text;
      text << in.rdbuf();
      const std::string s = text.str();
      ++files;
      if (std::regex_search(s, call)) ADD_FAILURE() << entry.path() << " calls remove_all: use remove_tree";
    }
  EXPECT_GT(files, 100);
}

}  // namespace
}  // namespace pb4u

// remove_tree (std::filesystem::remove_all without the symbol libtorch re-exports): a nested
// tree goes, links are removed but never followed, a missing path is no error.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>

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

}  // namespace
}  // namespace pb4u

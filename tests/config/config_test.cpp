// Typed config loading: defaults, overrides, and errors that name the file and key.
#include <gtest/gtest.h>

#include "pb4u/config/config_io.h"
#include "test_util.h"

namespace pb4u {
namespace {

struct Inner {
  double lr = 1e-3;
  int steps = 10;
  std::string kind = "pb4u";
  template <class V>
  void visit(V& v) {
    v("lr", lr, positive());
    v("steps", steps, int_at_least(1));
    v("kind", kind, one_of({"pb4u", "mgn"}));
  }
};

struct Root {
  Inner model;
  bool flag = false;
  std::vector<int> levels{1, 2};
  template <class V>
  void visit(V& v) {
    v("model", model);
    v("flag", flag);
    v("levels", levels);
  }
};

std::string write_yaml(const std::string& text) {
  std::string path = test::temp_dir("cfg") + "/c.yaml";
  test::write_file(path, text);
  return path;
}

std::string error_of(const std::string& file, std::vector<std::string> sets = {}) {
  try {
    load_config<Root>(file, sets);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Config, DefaultsFileAndOverrides) {
  std::string f = write_yaml("model:\n  lr: 0.01\nlevels: [1, 2, 3]\n");
  Root r = load_config<Root>(f, {"model.steps=42", "flag=true"});
  EXPECT_DOUBLE_EQ(r.model.lr, 0.01);
  EXPECT_EQ(r.model.steps, 42);
  EXPECT_EQ(r.model.kind, "pb4u");
  EXPECT_TRUE(r.flag);
  EXPECT_EQ(r.levels, (std::vector<int>{1, 2, 3}));
}

TEST(Config, RoundTripsThroughTheEffectiveConfig) {
  Root r = load_config<Root>("", {"model.kind=mgn", "model.lr=0.5"});
  std::string f = write_yaml(config_to_yaml(r));
  Root again = load_config<Root>(f);
  EXPECT_EQ(again.model.kind, "mgn");
  EXPECT_DOUBLE_EQ(again.model.lr, 0.5);
  EXPECT_EQ(config_to_yaml(again), config_to_yaml(r));
}

TEST(Config, UnknownKeyNamesFileAndPath) {
  std::string f = write_yaml("model:\n  lr: 0.01\n  widht: 3\n");
  std::string e = error_of(f);
  EXPECT_NE(e.find(f), std::string::npos) << e;
  EXPECT_NE(e.find("model.widht"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown key"), std::string::npos) << e;
}

TEST(Config, WrongTypeAndRangeNameThePath) {
  std::string e = error_of(write_yaml("model:\n  steps: many\n"));
  EXPECT_NE(e.find("model.steps"), std::string::npos) << e;
  EXPECT_NE(e.find("integer"), std::string::npos) << e;
  e = error_of(write_yaml("model:\n  lr: -1\n"));
  EXPECT_NE(e.find("model.lr"), std::string::npos) << e;
  EXPECT_NE(e.find("positive"), std::string::npos) << e;
  e = error_of(write_yaml("model:\n  kind: gnn\n"));
  EXPECT_NE(e.find("pb4u | mgn"), std::string::npos) << e;
  e = error_of(write_yaml("model: 3\n"));
  EXPECT_NE(e.find("expected a map"), std::string::npos) << e;
  e = error_of(write_yaml("levels: 3\n"));
  EXPECT_NE(e.find("expected a list"), std::string::npos) << e;
}

TEST(Config, BadOverridesNameSet) {
  std::string e = error_of("", {"model.nope=1"});
  EXPECT_NE(e.find("--set model.nope"), std::string::npos) << e;
  e = error_of("", {"model.lr=abc"});
  EXPECT_NE(e.find("--set model.lr"), std::string::npos) << e;
  e = error_of("", {"justakey"});
  EXPECT_NE(e.find("key.path=value"), std::string::npos) << e;
}

TEST(Config, BrokenOrMissingFiles) {
  std::string e = error_of(write_yaml("model: [1, 2\n"));
  EXPECT_NE(e.find("invalid YAML"), std::string::npos) << e;
  e = error_of("/nonexistent/c.yaml");
  EXPECT_NE(e.find("no such config file"), std::string::npos) << e;
  e = error_of(write_yaml("- 1\n- 2\n"));
  EXPECT_NE(e.find("map of keys"), std::string::npos) << e;
  // An empty file means "all defaults".
  EXPECT_EQ(error_of(write_yaml("")), "");
}

}  // namespace
}  // namespace pb4u

// Fuzzes typed config loading with a nested section, lists and every scalar type.
#include "fuzz_input.h"
#include "pb4u/config/config_io.h"
#include "pb4u/scene/material.h"

namespace {
struct FuzzConfig {
  pb4u::Material material;
  pb4u::MaterialRanges ranges;
  int steps = 1;
  bool flag = false;
  std::string kind = "a";
  std::vector<int> levels{1};
  template <class V>
  void visit(V& v) {
    v("material", material);
    v("ranges", ranges);
    v("steps", steps, pb4u::int_at_least(1));
    v("flag", flag);
    v("kind", kind, pb4u::one_of({"a", "b"}));
    v("levels", levels);
  }
};
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string path = pb4u::fuzz::write_input(data, size, ".yaml");
  try {
    auto cfg = pb4u::load_config<FuzzConfig>(path);
    pb4u::config_to_yaml(cfg);
  } catch (const pb4u::Error&) {
  }
  std::remove(path.c_str());
  return 0;
}

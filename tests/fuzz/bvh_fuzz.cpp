// Fuzzes read_bvh: hierarchy parsing, channel orders, motion rows and resampling to 30 fps.
#include "fuzz_input.h"
#include "pb4u/body/bvh.h"
#include "pb4u/util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string path = pb4u::fuzz::write_input(data, size, ".bvh");
  try {
    pb4u::read_bvh(path, 30.0, 0.01);
  } catch (const pb4u::Error&) {
  }
  std::remove(path.c_str());
  return 0;
}

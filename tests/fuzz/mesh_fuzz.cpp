// Fuzzes read_mesh: the first byte picks the file extension (and so assimp's importer).
#include "fuzz_input.h"
#include "pb4u/io/mesh_io.h"
#include "pb4u/io/mesh_summary.h"
#include "pb4u/util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const char* kExtensions[] = {".obj", ".ply", ".stl", ".off", ".gltf", ".glb", ".dae", ".fbx"};
  if (size < 1) return 0;
  std::string path = pb4u::fuzz::write_input(data + 1, size - 1, kExtensions[data[0] % 8]);
  try {
    pb4u::summarize_mesh_file(path);  // read, clean, and every topology query
  } catch (const pb4u::Error&) {
  }
  std::remove(path.c_str());
  return 0;
}

#pragma once
// libFuzzer targets feed bytes to pb4u's file loaders. The loaders take paths, so each input is
// written to a per-process temporary file first.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>

namespace pb4u::fuzz {

inline std::string write_input(const uint8_t* data, size_t size, const std::string& extension) {
  std::string path = "/tmp/pb4u_fuzz_" + std::to_string(::getpid()) + extension;
  if (FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data, 1, size, f);
    std::fclose(f);
  }
  return path;
}

}  // namespace pb4u::fuzz

#include "pb4u/io/point_cache.h"

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "pb4u/util/atomic_file.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace {
constexpr char kMagic[12] = "POINTCACHE2";  // with its terminating zero: 12 bytes
}

void write_pc2(const std::string& path, const std::vector<Eigen::MatrixXd>& frames,
               double start_frame) {
  const int32_t n = frames.empty() ? 0 : static_cast<int32_t>(frames[0].rows());
  for (const auto& f : frames)
    if (f.rows() != n || f.cols() != 3) fail_file(path, "point cache frames differ in vertex count");
  AtomicFile file(path, /*binary=*/true);
  auto& out = file.stream();
  const int32_t version = 1, samples = static_cast<int32_t>(frames.size());
  const float start = static_cast<float>(start_frame), rate = 1.0f;
  out.write(kMagic, sizeof kMagic);
  out.write(reinterpret_cast<const char*>(&version), 4);
  out.write(reinterpret_cast<const char*>(&n), 4);
  out.write(reinterpret_cast<const char*>(&start), 4);
  out.write(reinterpret_cast<const char*>(&rate), 4);
  out.write(reinterpret_cast<const char*>(&samples), 4);
  std::vector<float> buf(static_cast<size_t>(n) * 3);
  for (const auto& f : frames) {
    for (int32_t v = 0; v < n; ++v)
      for (int k = 0; k < 3; ++k) buf[3 * v + k] = static_cast<float>(f(v, k));
    out.write(reinterpret_cast<const char*>(buf.data()), static_cast<std::streamsize>(buf.size() * 4));
  }
  file.commit();
}

std::vector<Eigen::MatrixXd> read_pc2(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail_file(path, "cannot open point cache");
  char magic[12];
  int32_t version = 0, n = 0, samples = 0;
  float start = 0, rate = 0;
  in.read(magic, 12);
  in.read(reinterpret_cast<char*>(&version), 4);
  in.read(reinterpret_cast<char*>(&n), 4);
  in.read(reinterpret_cast<char*>(&start), 4);
  in.read(reinterpret_cast<char*>(&rate), 4);
  in.read(reinterpret_cast<char*>(&samples), 4);
  if (!in || std::memcmp(magic, kMagic, 12) != 0) fail_file(path, "not a PC2 point cache");
  if (n < 0 || samples < 0) fail_file(path, "negative counts in the PC2 header");
  std::error_code ec;
  auto size = std::filesystem::file_size(path, ec);
  if (size != 32 + static_cast<uintmax_t>(n) * samples * 12)
    fail_file(path, "PC2 size does not match its header (truncated?)");
  std::vector<Eigen::MatrixXd> frames(samples, Eigen::MatrixXd(n, 3));
  std::vector<float> buf(static_cast<size_t>(n) * 3);
  for (auto& f : frames) {
    in.read(reinterpret_cast<char*>(buf.data()), static_cast<std::streamsize>(buf.size() * 4));
    for (int32_t v = 0; v < n; ++v)
      for (int k = 0; k < 3; ++k) f(v, k) = buf[3 * v + k];
  }
  return frames;
}

}  // namespace pb4u

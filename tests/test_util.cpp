#include "test_util.h"

#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <mutex>
#include <vector>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "pb4u/util/remove_tree.h"

namespace pb4u::test {
namespace fs = std::filesystem;

namespace {

// The directories temp_dir made in this process, removed when it exits (PB4U_KEEP_TEST_DIRS=1
// keeps them to look at).
std::mutex made_mutex;
std::vector<std::string>& made() {
  static auto* dirs = new std::vector<std::string>;  // never destroyed: read at exit
  return *dirs;
}
void remove_made_dirs() {
  const char* keep = std::getenv("PB4U_KEEP_TEST_DIRS");
  if (keep && std::string(keep) == "1") return;
  std::lock_guard<std::mutex> lock(made_mutex);
  for (const auto& dir : made()) remove_tree(dir);
}

}  // namespace

std::string temp_dir(const std::string& tag) {
  static std::atomic<int> counter{0};
  fs::path dir = fs::temp_directory_path() /
                 ("pb4u_test_" + tag + "_" + std::to_string(::getpid()) + "_" +
                  std::to_string(counter++));
  remove_tree(dir.string());  // not fs::remove_all: see remove_tree.h
  fs::create_directories(dir);
  std::lock_guard<std::mutex> lock(made_mutex);
  if (made().empty()) std::atexit(remove_made_dirs);
  made().push_back(dir.string());
  return dir.string();
}

void write_file(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

CommandResult run_pb4u(const std::string& args) {
  std::string dir = temp_dir("cmd");
  std::string out = dir + "/out.txt", err = dir + "/err.txt";
  std::string cmd = std::string(PB4U_BINARY) + " " + args + " >" + out + " 2>" + err + " </dev/null";
  int status = std::system(cmd.c_str());
  CommandResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.out = read_file(out);
  r.err = read_file(err);
  remove_tree(dir);
  return r;
}

namespace {

// configs/data/<name>.yaml generated with the real `pb4u generate` into a fresh folder.
std::string generated_dataset(const std::string& name) {
  std::string dir = temp_dir(name + "data");
  CommandResult r = run_pb4u("-q generate --config " + std::string(PB4U_SOURCE_DIR) + "/configs/data/" + name +
                             ".yaml --out " + dir);
  if (r.exit_code != 0) throw std::runtime_error(name + " dataset: " + r.err);
  return dir + "/" + name + ".h5";
}

}  // namespace

const std::string& tiny_dataset() {
  static const std::string path = generated_dataset("tiny");
  return path;
}

const std::string& hard_dataset() {
  static const std::string path = generated_dataset("hard");
  return path;
}

TriMesh lattice_cloth(int res_x, int res_y, double dx, int thin_row, double thin_height) {
  const double dy = dx * std::sqrt(3.0) / 2;
  TriMesh m;
  m.V.resize(res_x * res_y, 3);
  double y = 1.0;
  for (int r = 0; r < res_y; ++r) {
    for (int c = 0; c < res_x; ++c) m.V.row(r * res_x + c) << c * dx + (r % 2) * dx / 2, y, 0.0;
    y -= r == thin_row ? thin_height : dy;
  }
  m.F.resize(2 * (res_x - 1) * (res_y - 1), 3);
  int f = 0;
  for (int r = 0; r + 1 < res_y; ++r)
    for (int c = 0; c + 1 < res_x; ++c) {
      const int t0 = r * res_x + c, t1 = t0 + 1, b0 = t0 + res_x, b1 = b0 + 1;
      // Rows go down (-y) and columns right (+x): (t, b, ...) counter-clockwise seen from +z.
      if (r % 2 == 0) {
        m.F.row(f++) << t0, b0, t1;
        m.F.row(f++) << t1, b0, b1;
      } else {
        m.F.row(f++) << t0, b0, b1;
        m.F.row(f++) << t0, b1, t1;
      }
    }
  return m;
}

TriMesh grid_mesh(int n, double size) {
  TriMesh m;
  m.V.resize((n + 1) * (n + 1), 3);
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) m.V.row(i * (n + 1) + j) << size * j / n, 0.0, size * i / n;
  m.F.resize(2 * n * n, 3);
  int f = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      int a = i * (n + 1) + j, b = a + 1, c = a + n + 1, d = c + 1;
      // Normals point up (+y): (b - a) x (c - a) = x-axis x z-axis = -y, so order a, c, b.
      m.F.row(f++) << a, c, b;
      m.F.row(f++) << b, c, d;
    }
  return m;
}

TriMesh box_mesh(const Eigen::RowVector3d& lo, const Eigen::RowVector3d& hi) {
  TriMesh m;
  m.V.resize(8, 3);
  for (int i = 0; i < 8; ++i) m.V.row(i) << (i & 1 ? hi : lo)(0), (i & 2 ? hi : lo)(1), (i & 4 ? hi : lo)(2);
  // Corner i has x from bit 0, y from bit 1, z from bit 2; each side counter-clockwise seen from outside.
  m.F.resize(12, 3);
  m.F << 0, 2, 3, 0, 3, 1,  // z = lo
      4, 5, 7, 4, 7, 6,     // z = hi
      0, 1, 5, 0, 5, 4,     // y = lo
      2, 6, 7, 2, 7, 3,     // y = hi
      0, 4, 6, 0, 6, 2,     // x = lo
      1, 3, 7, 1, 7, 5;     // x = hi
  return m;
}

TriMesh joined(const TriMesh& a, const TriMesh& b) {
  TriMesh m;
  m.V.resize(a.V.rows() + b.V.rows(), 3);
  m.V << a.V, b.V;
  m.F.resize(a.F.rows() + b.F.rows(), 3);
  m.F << a.F, (b.F.array() + int(a.V.rows())).matrix();
  return m;
}

}  // namespace pb4u::test

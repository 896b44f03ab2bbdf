#include "pb4u/io/preview.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>

#include <unistd.h>

#include "pb4u/spatial/winding_number.h"
#include "pb4u/util/error.h"
#include "pb4u/util/plot_script.h"
#include "pb4u/util/remove_tree.h"

namespace pb4u {
namespace fs = std::filesystem;

namespace {

// OBJ with the common "v x y z r g b" extension: red for a garment vertex inside the body.
void write_colored_obj(const std::string& path, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                       const std::vector<bool>& inside) {
  std::ofstream out(path);
  char line[160];
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    if (inside.empty()) std::snprintf(line, sizeof line, "v %.7g %.7g %.7g\n", V(i, 0), V(i, 1), V(i, 2));
    else std::snprintf(line, sizeof line, "v %.7g %.7g %.7g %d 0 0\n", V(i, 0), V(i, 1), V(i, 2), inside[i] ? 1 : 0);
    out << line;
  }
  for (Eigen::Index f = 0; f < F.rows(); ++f) out << "f " << F(f, 0) + 1 << ' ' << F(f, 1) + 1 << ' ' << F(f, 2) + 1 << '\n';
}

std::vector<bool> inside_body(const Eigen::MatrixXd& garment, const Eigen::MatrixXd& body, const Eigen::MatrixXi& faces) {
  std::vector<bool> inside(garment.rows(), false);
  if (faces.rows() == 0 || !garment.allFinite()) return inside;
  // As physics/penetration.h counts them: wrapped by the body (also where its parts overlap).
  const Eigen::VectorXi wraps = WindingNumbers(body, faces).at(garment);
  for (Eigen::Index i = 0; i < wraps.size(); ++i) inside[i] = wraps[i] >= 1;
  return inside;
}

}  // namespace

std::vector<int> preview_frames(int num_frames, int count) {
  std::set<int> picked;
  if (num_frames <= 0) return {};
  count = std::max(1, std::min(count, num_frames));
  for (int k = 0; k < count; ++k)
    picked.insert(count == 1 ? num_frames - 1 : static_cast<int>(std::lround(double(k) * (num_frames - 1) / (count - 1))));
  return {picked.begin(), picked.end()};
}

bool write_preview(const std::string& png, const std::vector<int>& frames, const std::vector<Eigen::MatrixXd>& garment,
                   const Eigen::MatrixXi& garment_faces, const std::vector<Eigen::MatrixXd>& body,
                   const Eigen::MatrixXi& body_faces, const std::string& title) {
  const bool with_body = body_faces.rows() > 0;
  std::error_code ec;
  const fs::path tmp = fs::temp_directory_path(ec) / ("pb4u_preview_" + std::to_string(::getpid()) + "_" +
                                                      std::to_string(std::hash<std::string>{}(png) % 100000));
  fs::create_directories(tmp, ec);
  if (ec) {
    spdlog::warn("preview: cannot make a temporary folder ({}); no {}", ec.message(), png);
    return false;
  }
  std::vector<std::string> args{png, "--title", title};
  for (int f : frames) {
    if (f < 0 || f >= int(garment.size())) continue;
    const std::string g = (tmp / ("garment_" + std::to_string(f) + ".obj")).string();
    std::vector<bool> inside;
    std::string spec = std::to_string(f) + ":" + g;
    if (with_body && f < int(body.size())) {
      inside = inside_body(garment[f], body[f], body_faces);
      const std::string b = (tmp / ("body_" + std::to_string(f) + ".obj")).string();
      write_colored_obj(b, body[f], body_faces, {});
      spec += ":" + b;
    }
    write_colored_obj(g, garment[f], garment_faces, inside);
    args.push_back(spec);
  }
  const bool ok = run_plot_script("plot_preview.py", args) && fs::exists(png);
  try {
    remove_tree(tmp.string());
  } catch (const Error& e) {
    spdlog::warn("preview: {}", e.what());  // a leftover temp folder is not worth failing for
  }
  return ok;
}

}  // namespace pb4u

#include "pb4u/sim/rollout_writer.h"

#include <cstdio>
#include <sstream>

#include "pb4u/io/hdf5_file.h"
#include "pb4u/io/mesh_io.h"
#include "pb4u/io/point_cache.h"
#include "pb4u/io/usd_cache.h"
#include "pb4u/util/atomic_file.h"
#include "pb4u/util/error.h"

namespace pb4u {

std::string frame_file(const std::string& dir, const std::string& stem, int frame,
                       const std::string& ext) {
  char name[64];
  std::snprintf(name, sizeof name, "%s_%04d.%s", stem.c_str(), frame, ext.c_str());
  return dir + "/" + name;
}

RolloutWriter::RolloutWriter(std::string out_dir, Eigen::MatrixXi garment_faces,
                             Eigen::MatrixXi body_faces, RolloutOutputs outputs)
    : dir_(std::move(out_dir)), garment_faces_(std::move(garment_faces)),
      body_faces_(std::move(body_faces)), outputs_(std::move(outputs)) {
  if (outputs_.mesh_format != "obj" && outputs_.mesh_format != "ply" && outputs_.mesh_format != "none")
    throw Error("outputs.mesh_format: must be obj | ply | none, got '" + outputs_.mesh_format + "'");
}

void RolloutWriter::set_rest_and_previous(const Eigen::MatrixXd& rest, const Eigen::MatrixXd& previous) {
  rest_ = rest;
  previous_ = previous;
  if (outputs_.mesh_format != "none") {
    const std::string path = dir_ + "/garment_rest." + outputs_.mesh_format;
    write_mesh(path, TriMesh{rest, garment_faces_});
    written_.push_back(path);
  }
}

void RolloutWriter::add_frame(const Eigen::MatrixXd& garment, const Eigen::MatrixXd& body,
                              const std::vector<std::pair<std::string, double>>& energies) {
  const int frame = num_frames();
  if (frame == 0)
    for (const auto& e : energies) energy_names_.push_back(e.first);
  std::vector<double> values;
  for (size_t i = 0; i < energies.size(); ++i) {
    if (i >= energy_names_.size() || energies[i].first != energy_names_[i])
      throw Error("rollout: energy terms changed between frames");
    values.push_back(energies[i].second);
  }
  const bool has_body = body_faces_.rows() > 0;
  if (outputs_.mesh_format != "none") {
    std::string path = frame_file(dir_, "garment", frame, outputs_.mesh_format);
    write_mesh(path, TriMesh{garment, garment_faces_});
    written_.push_back(path);
    if (has_body) {
      path = frame_file(dir_, "body", frame, outputs_.mesh_format);
      write_mesh(path, TriMesh{body, body_faces_});
      written_.push_back(path);
    }
  }
  garment_frames_.push_back(garment);
  if (has_body) body_frames_.push_back(body);
  energies_.push_back(std::move(values));
}

namespace {

// group/positions (T x n x 3 float64) and group/faces (F x 3 int32).
void write_frames_dataset(Hdf5Group& group, const std::vector<Eigen::MatrixXd>& frames,
                          const Eigen::MatrixXi& faces) {
  const size_t T = frames.size(), n = T ? frames[0].rows() : 0;
  std::vector<double> pos(T * n * 3);
  for (size_t t = 0; t < T; ++t)
    for (size_t v = 0; v < n; ++v)
      for (int k = 0; k < 3; ++k) pos[(t * n + v) * 3 + k] = frames[t](v, k);
  group.write("positions", {T, n, 3}, pos.data());
  std::vector<int32_t> f(static_cast<size_t>(faces.rows()) * 3);
  for (Eigen::Index i = 0; i < faces.rows(); ++i)
    for (int k = 0; k < 3; ++k) f[i * 3 + k] = faces(i, k);
  group.write("faces", {static_cast<size_t>(faces.rows()), 3}, f.data());
}

// n x 3 float64 positions as group/name.
void write_positions(Hdf5Group& group, const std::string& name, const Eigen::MatrixXd& x) {
  std::vector<double> buf(static_cast<size_t>(x.rows()) * 3);
  for (Eigen::Index v = 0; v < x.rows(); ++v)
    for (int k = 0; k < 3; ++k) buf[v * 3 + k] = x(v, k);
  group.write(name, {static_cast<size_t>(x.rows()), 3}, buf.data());
}

}  // namespace

std::vector<std::string> RolloutWriter::finish() {
  const bool has_body = body_faces_.rows() > 0;
  if (outputs_.point_cache) {
    write_pc2(dir_ + "/garment.pc2", garment_frames_);
    written_.push_back(dir_ + "/garment.pc2");
    if (has_body) {
      write_pc2(dir_ + "/body.pc2", body_frames_);
      written_.push_back(dir_ + "/body.pc2");
    }
  }
  if (outputs_.usd_cache && !garment_frames_.empty()) {
    UsdCache usd;
    usd.fps = outputs_.fps;
    usd.meshes.push_back({"Garment", garment_faces_, garment_frames_, Eigen::Vector3d(0.85, 0.33, 0.22)});
    if (has_body) usd.meshes.push_back({"Body", body_faces_, body_frames_, Eigen::Vector3d(0.72, 0.72, 0.75)});
    write_usd_cache(dir_ + "/scene.usda", usd);
    written_.push_back(dir_ + "/scene.usda");
  }
  if (outputs_.energies_csv) {
    AtomicFile csv(dir_ + "/energies.csv");
    csv.stream() << "frame";
    for (const auto& name : energy_names_) csv.stream() << ',' << name;
    csv.stream() << '\n';
    char buf[32];
    for (size_t t = 0; t < energies_.size(); ++t) {
      csv.stream() << t;
      for (double v : energies_[t]) {
        std::snprintf(buf, sizeof buf, ",%.9g", v);
        csv.stream() << buf;
      }
      csv.stream() << '\n';
    }
    csv.commit();
    written_.push_back(dir_ + "/energies.csv");
  }
  if (outputs_.hdf5) {
    const std::string path = dir_ + "/rollout.h5";
    write_hdf5(path, [&](Hdf5Group& file) {
      Hdf5Group g = file.create_group("garment");
      write_frames_dataset(g, garment_frames_, garment_faces_);
      if (rest_.rows()) write_positions(g, "rest", rest_);
      if (previous_.rows()) write_positions(g, "previous", previous_);
      if (has_body) {
        Hdf5Group b = file.create_group("body");
        write_frames_dataset(b, body_frames_, body_faces_);
      }
      Hdf5Group e = file.create_group("energies");
      for (size_t i = 0; i < energy_names_.size(); ++i) {
        std::vector<double> col;
        for (const auto& row : energies_) col.push_back(row[i]);
        e.write(energy_names_[i], {col.size()}, col.data());
      }
      file.set_attribute("fps", outputs_.fps);
    });
    written_.push_back(path);
  }
  return written_;
}

}  // namespace pb4u

#include "pb4u/data/dataset.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "pb4u/body/forward_kinematics.h"
#include "pb4u/io/hdf5_file.h"
#include "pb4u/mesh/geometry.h"
#include "pb4u/util/error.h"

namespace pb4u {

const BodyRecord* Dataset::find_body(const std::string& name) const {
  for (const auto& b : bodies)
    if (b.body.name == name) return &b;
  return nullptr;
}

namespace {

constexpr const char* kFormat = "pb4u-dataset";
constexpr int kVersion = 1;

using RowMatrixXd = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using RowMatrixXf = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using RowMatrixXi = Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// ---- writing ----
// Every numeric array is compressed when large (Hdf5Group::write's `compress`).

void write_matrix(Hdf5Group& g, const std::string& name, const Eigen::MatrixXd& M) {
  RowMatrixXd R = M;
  g.write(name, {size_t(R.rows()), size_t(R.cols())}, R.data(), true);
}
void write_matrix_f32(Hdf5Group& g, const std::string& name, const Eigen::MatrixXd& M) {
  RowMatrixXf R = M.cast<float>();
  g.write(name, {size_t(R.rows()), size_t(R.cols())}, R.data(), true);
}
void write_matrix(Hdf5Group& g, const std::string& name, const Eigen::MatrixXi& M) {
  RowMatrixXi R = M;
  g.write(name, {size_t(R.rows()), size_t(R.cols())}, R.data(), true);
}

Eigen::MatrixXd quaternions(const std::vector<Eigen::Quaterniond>& q) {
  Eigen::MatrixXd M(q.size(), 4);
  for (size_t i = 0; i < q.size(); ++i) M.row(i) << q[i].w(), q[i].x(), q[i].y(), q[i].z();
  return M;
}

void write_skeleton(Hdf5Group& g, const Skeleton& s, const Pose& bind) {
  g.write_strings("joint_names", s.names);
  Eigen::MatrixXi parents(s.num_joints(), 1);
  for (int j = 0; j < s.num_joints(); ++j) parents(j, 0) = s.parents[j];
  write_matrix(g, "parents", parents);
  write_matrix(g, "offsets", s.offsets);
  write_matrix(g, "bind_rotations", quaternions(bind.rotations));
  write_matrix(g, "bind_root", Eigen::MatrixXd(bind.root.transpose()));
}

void write_mesh_group(Hdf5Group& g, const TriMesh& mesh, const Eigen::MatrixXd& weights) {
  write_matrix(g, "vertices", mesh.V);
  write_matrix(g, "faces", mesh.F);
  write_matrix_f32(g, "skin_weights", weights);
}

// ---- reading ----

struct Reader {
  std::string path;

  [[noreturn]] void fail(const std::string& where, const std::string& why) const {
    fail_file(path, where + ": " + why);
  }

  // A 2-D dataset (`cols` columns unless cols <= 0) as a matrix, converted to Row's scalar.
  template <class Matrix, class Row>
  Matrix read(const Hdf5Group& g, const std::string& name, Eigen::Index cols) const {
    const std::vector<size_t> d = g.shape(name);
    if (d.size() != 2 || (cols > 0 && d[1] != size_t(cols))) fail(g.child_path(name), "unexpected shape");
    Row R(d[0], d[1]);
    if (R.size() > 0) g.read(name, R.data());
    return Matrix(R);
  }
  Eigen::MatrixXd matrix(const Hdf5Group& g, const std::string& name, Eigen::Index cols = -1) const {
    Eigen::MatrixXd M = read<Eigen::MatrixXd, RowMatrixXd>(g, name, cols);
    if (!M.allFinite()) fail(g.child_path(name), "non-finite values");
    return M;
  }
  Eigen::MatrixXi imatrix(const Hdf5Group& g, const std::string& name, Eigen::Index cols = -1) const {
    return read<Eigen::MatrixXi, RowMatrixXi>(g, name, cols);
  }

  void check_mesh(const TriMesh& m, const Eigen::MatrixXd& W, const std::string& gp) const {
    if (m.F.rows() == 0) fail(gp, "no faces");
    if (m.F.minCoeff() < 0 || m.F.maxCoeff() >= m.V.rows()) fail(gp + "/faces", "index out of range");
    if (W.rows() != m.V.rows()) fail(gp + "/skin_weights", "row count differs from vertices");
  }

  std::vector<Eigen::Quaterniond> quats(const Eigen::MatrixXd& M) const {
    std::vector<Eigen::Quaterniond> q(M.rows());
    for (Eigen::Index i = 0; i < M.rows(); ++i)
      q[i] = Eigen::Quaterniond(M(i, 0), M(i, 1), M(i, 2), M(i, 3)).normalized();
    return q;
  }
};

}  // namespace

void write_dataset(const std::string& path, const Dataset& data) {
  write_hdf5(path, [&](Hdf5Group& root) {
    root.set_attribute("format", std::string(kFormat));
    root.set_attribute("version", kVersion);
    root.set_attribute("density", data.density);
    root.set_attribute("config", data.config_yaml);
    Hdf5Group levels = root.create_group("levels");
    Eigen::MatrixXi t(data.level_triangles.size(), 1);
    for (size_t k = 0; k < data.level_triangles.size(); ++k) t(k, 0) = data.level_triangles[k];
    write_matrix(levels, "triangles", t);
    Hdf5Group bodies = root.create_group("bodies");
    for (const BodyRecord& rec : data.bodies) {
      const Body& b = rec.body;
      Hdf5Group g = bodies.create_group(b.name);
      write_mesh_group(g, b.mesh, b.weights);
      Hdf5Group sk = g.create_group("skeleton");
      write_skeleton(sk, b.skeleton, b.bind);
      Hdf5Group garments = g.create_group("garments");
      for (const GarmentLevels& gl : rec.garments) {
        Hdf5Group gg = garments.create_group(gl.name);
        for (size_t k = 0; k < gl.levels.size(); ++k) {
          const Garment& gar = gl.levels[k];
          Hdf5Group lg = gg.create_group("level_" + std::to_string(k + 1));
          write_mesh_group(lg, gar.mesh, gar.weights);
          write_matrix(lg, "masses", Eigen::MatrixXd(vertex_masses(gar.mesh.V, gar.mesh.F, data.density)));
          lg.set_attribute("target_triangles", k < data.level_triangles.size() ? data.level_triangles[k] : 0);
          lg.set_attribute("mean_edge_length", mean_edge_length(gar.mesh.V, gar.mesh.F));
        }
      }
    }
    Hdf5Group motions = root.create_group("motions");
    std::vector<std::string> train, test, heldout;
    for (const MotionRecord& m : data.motions) {
      Hdf5Group g = motions.create_group(m.name);
      g.set_attribute("body", m.body);
      g.set_attribute("source", m.source);
      g.set_attribute("split", m.split);
      g.set_attribute("fps", m.motion.fps);
      const int T = m.motion.num_frames();
      const int J = T > 0 ? static_cast<int>(m.motion.frames[0].rotations.size()) : 0;
      Eigen::MatrixXd root_translation(T, 3), rot(T, 4 * J);
      for (int f = 0; f < T; ++f) {
        root_translation.row(f) = m.motion.frames[f].root.transpose();
        Eigen::MatrixXd q = quaternions(m.motion.frames[f].rotations);
        for (int j = 0; j < J; ++j) rot.block(f, 4 * j, 1, 4) = q.row(j);
      }
      write_matrix(g, "root_translation", root_translation);
      RowMatrixXd R = rot;
      g.write("rotations", {size_t(T), size_t(J), 4}, R.data(), true);
      (m.split == "test" ? test : m.split == "heldout" ? heldout : train).push_back(m.name);
    }
    Hdf5Group split = root.create_group("split");
    split.write_strings("train", train);
    split.write_strings("test", test);
    if (!heldout.empty()) split.write_strings("heldout", heldout);
  });
}

Dataset read_dataset(const std::string& path) {
  Reader r{path};
  const Hdf5Group root = open_hdf5(path);
  Dataset data;
  if (!root.has_attribute("format") || root.string_attribute("format") != kFormat)
    fail_file(path, "not a pb4u dataset (no format attribute 'pb4u-dataset')");
  data.density = root.double_attribute("density");
  data.config_yaml = root.string_attribute("config");
  const Eigen::MatrixXi t = r.imatrix(root.group("levels"), "triangles", 1);
  data.level_triangles.assign(t.data(), t.data() + t.size());
  const Hdf5Group bodies = root.group("bodies");
  for (const std::string& name : bodies.children()) {
    const Hdf5Group g = bodies.group(name);
    const std::string& gp = g.name();
    BodyRecord rec;
    Body& b = rec.body;
    b.name = name;
    b.mesh.V = r.matrix(g, "vertices", 3);
    b.mesh.F = r.imatrix(g, "faces", 3);
    b.weights = r.read<Eigen::MatrixXd, RowMatrixXd>(g, "skin_weights", -1);
    r.check_mesh(b.mesh, b.weights, gp);
    const Hdf5Group sk = g.group("skeleton");
    const std::string& sp = sk.name();
    b.skeleton.names = sk.read_strings("joint_names");
    const Eigen::MatrixXi parents = r.imatrix(sk, "parents", 1);
    b.skeleton.parents.assign(parents.data(), parents.data() + parents.size());
    b.skeleton.offsets = r.matrix(sk, "offsets", 3);
    validate_skeleton(b.skeleton, path + ": " + sp);
    const int J = b.skeleton.num_joints();
    if (b.weights.cols() != J) r.fail(gp + "/skin_weights", "column count differs from joints");
    const Eigen::MatrixXd bind = r.matrix(sk, "bind_rotations", 4);
    if (bind.rows() != J) r.fail(sp + "/bind_rotations", "one row per joint expected");
    b.bind.rotations = r.quats(bind);
    b.bind.root = r.matrix(sk, "bind_root", 3).row(0).transpose();
    if (g.has("garments")) {
      const Hdf5Group garments = g.group("garments");
      for (const std::string& gname : garments.children()) {
        const Hdf5Group gg = garments.group(gname);
        GarmentLevels gl;
        gl.name = gname;
        for (size_t k = 1; gg.has("level_" + std::to_string(k)); ++k) {
          const Hdf5Group lg = gg.group("level_" + std::to_string(k));
          Garment gar;
          gar.name = gname;
          gar.mesh.V = r.matrix(lg, "vertices", 3);
          gar.mesh.F = r.imatrix(lg, "faces", 3);
          gar.weights = r.read<Eigen::MatrixXd, RowMatrixXd>(lg, "skin_weights", J);
          r.check_mesh(gar.mesh, gar.weights, lg.name());
          gl.levels.push_back(std::move(gar));
        }
        rec.garments.push_back(std::move(gl));
      }
    }
    data.bodies.push_back(std::move(rec));
  }
  if (root.has("motions")) {
    const Hdf5Group motions = root.group("motions");
    for (const std::string& name : motions.children()) {
      const Hdf5Group g = motions.group(name);
      const std::string& mp = g.name();
      MotionRecord m;
      m.name = name;
      m.body = g.string_attribute("body");
      m.source = g.string_attribute("source");
      m.split = g.string_attribute("split");
      m.motion.fps = g.double_attribute("fps");
      const BodyRecord* body = data.find_body(m.body);
      if (!body) r.fail(mp, "body '" + m.body + "' is not in the file");
      const int J = body->body.skeleton.num_joints();
      const Eigen::MatrixXd root_translation = r.matrix(g, "root_translation", 3);
      const std::vector<size_t> d = g.shape("rotations");
      if (d.size() != 3 || d[0] != size_t(root_translation.rows()) || d[1] != size_t(J) || d[2] != 4)
        r.fail(mp + "/rotations", "expected frames x joints x 4");
      RowMatrixXd rot(d[0], 4 * J);
      if (rot.size() > 0) g.read("rotations", rot.data());
      if (!rot.allFinite()) r.fail(mp + "/rotations", "non-finite values");
      for (Eigen::Index f = 0; f < root_translation.rows(); ++f) {
        Pose p;
        p.root = root_translation.row(f).transpose();
        p.rotations = r.quats(Eigen::Map<RowMatrixXd>(rot.row(f).data(), J, 4));
        m.motion.frames.push_back(std::move(p));
      }
      data.motions.push_back(std::move(m));
    }
  }
  return data;
}

void print_dataset_summary(std::ostream& out, const Dataset& d) {
  out << "kind: dataset\n";
  out << "levels:";
  for (int t : d.level_triangles) out << " " << t;
  out << " (target triangles)\n";
  out << "density: " << d.density << " kg/m^2\n";
  for (const BodyRecord& rec : d.bodies) {
    const Body& b = rec.body;
    out << "body " << b.name << ": " << b.mesh.num_vertices() << " vertices, " << b.mesh.num_faces()
        << " faces, " << b.skeleton.num_joints() << " joints, height "
        << bounding_box(b.mesh.V)(1, 1) - bounding_box(b.mesh.V)(0, 1) << " m\n";
    for (const GarmentLevels& gl : rec.garments) {
      out << "  garment " << gl.name << ": triangles";
      for (const Garment& g : gl.levels) out << " " << g.mesh.num_faces();
      out << "; mean edge (mm)";
      for (const Garment& g : gl.levels)
        out << " " << static_cast<int>(std::round(1000 * mean_edge_length(g.mesh.V, g.mesh.F)));
      out << "\n";
    }
  }
  int train = 0, test = 0, heldout = 0, frames = 0;
  for (const MotionRecord& m : d.motions) {
    (m.split == "test" ? test : m.split == "heldout" ? heldout : train)++;
    frames += m.motion.num_frames();
  }
  out << "motions: " << d.motions.size() << " (" << train << " train, " << test << " test";
  if (heldout > 0) out << ", " << heldout << " held out";
  out << "), " << frames << " frames\n";
  for (const MotionRecord& m : d.motions)
    out << "  " << m.name << ": " << m.motion.num_frames() << " frames at " << m.motion.fps
        << " fps, body " << m.body << ", " << m.split << ", " << m.source << "\n";
}

}  // namespace pb4u

#include "pb4u/data/dataset.h"

#include <H5Cpp.h>

#include <algorithm>
#include <cstdio>
#include <map>

#include "pb4u/body/forward_kinematics.h"
#include "pb4u/mesh/geometry.h"
#include "pb4u/util/atomic_file.h"
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

void write_array(H5::Group& g, const std::string& name, const void* data,
                 const H5::PredType& type, std::vector<hsize_t> dims) {
  H5::DataSpace space(static_cast<int>(dims.size()), dims.data());
  H5::DSetCreatPropList props;
  hsize_t total = 1;
  for (hsize_t d : dims) total *= d;
  if (total >= 4096) {  // compress the big arrays; chunk along the first axis
    std::vector<hsize_t> chunk = dims;
    chunk[0] = std::max<hsize_t>(1, std::min<hsize_t>(dims[0], (hsize_t(1) << 16) / std::max<hsize_t>(1, total / dims[0])));
    props.setChunk(static_cast<int>(chunk.size()), chunk.data());
    props.setDeflate(4);
  }
  H5::DataSet ds = g.createDataSet(name, type, space, props);
  ds.write(data, type);
}

void write_matrix(H5::Group& g, const std::string& name, const Eigen::MatrixXd& M) {
  RowMatrixXd R = M;
  write_array(g, name, R.data(), H5::PredType::NATIVE_DOUBLE, {hsize_t(R.rows()), hsize_t(R.cols())});
}
void write_matrix_f32(H5::Group& g, const std::string& name, const Eigen::MatrixXd& M) {
  RowMatrixXf R = M.cast<float>();
  write_array(g, name, R.data(), H5::PredType::NATIVE_FLOAT, {hsize_t(R.rows()), hsize_t(R.cols())});
}
void write_matrix(H5::Group& g, const std::string& name, const Eigen::MatrixXi& M) {
  RowMatrixXi R = M;
  write_array(g, name, R.data(), H5::PredType::NATIVE_INT, {hsize_t(R.rows()), hsize_t(R.cols())});
}

void write_strings(H5::Group& g, const std::string& name, const std::vector<std::string>& s) {
  size_t len = 1;
  for (const auto& x : s) len = std::max(len, x.size());
  std::vector<char> buf(std::max<size_t>(1, s.size()) * len, '\0');
  for (size_t i = 0; i < s.size(); ++i) std::copy(s[i].begin(), s[i].end(), buf.begin() + i * len);
  H5::StrType type(H5::PredType::C_S1, len);
  hsize_t dims[1] = {s.size()};
  H5::DataSpace space(1, dims);
  H5::DataSet ds = g.createDataSet(name, type, space);
  if (!s.empty()) ds.write(buf.data(), type);
}

void write_attr(H5::H5Object& o, const std::string& name, const std::string& value) {
  H5::StrType type(H5::PredType::C_S1, std::max<size_t>(1, value.size()));
  H5::Attribute a = o.createAttribute(name, type, H5::DataSpace(H5S_SCALAR));
  std::string padded = value.empty() ? std::string(1, '\0') : value;
  a.write(type, padded.data());
}
void write_attr(H5::H5Object& o, const std::string& name, double value) {
  H5::Attribute a = o.createAttribute(name, H5::PredType::NATIVE_DOUBLE, H5::DataSpace(H5S_SCALAR));
  a.write(H5::PredType::NATIVE_DOUBLE, &value);
}
void write_attr(H5::H5Object& o, const std::string& name, int value) {
  H5::Attribute a = o.createAttribute(name, H5::PredType::NATIVE_INT, H5::DataSpace(H5S_SCALAR));
  a.write(H5::PredType::NATIVE_INT, &value);
}

Eigen::MatrixXd quaternions(const std::vector<Eigen::Quaterniond>& q) {
  Eigen::MatrixXd M(q.size(), 4);
  for (size_t i = 0; i < q.size(); ++i) M.row(i) << q[i].w(), q[i].x(), q[i].y(), q[i].z();
  return M;
}

void write_skeleton(H5::Group& g, const Skeleton& s, const Pose& bind) {
  write_strings(g, "joint_names", s.names);
  Eigen::MatrixXi parents(s.num_joints(), 1);
  for (int j = 0; j < s.num_joints(); ++j) parents(j, 0) = s.parents[j];
  write_matrix(g, "parents", parents);
  write_matrix(g, "offsets", s.offsets);
  write_matrix(g, "bind_rotations", quaternions(bind.rotations));
  write_matrix(g, "bind_root", Eigen::MatrixXd(bind.root.transpose()));
}

void write_mesh_group(H5::Group& g, const TriMesh& mesh, const Eigen::MatrixXd& weights) {
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

  std::vector<hsize_t> dims(const H5::DataSet& ds) const {
    H5::DataSpace space = ds.getSpace();
    std::vector<hsize_t> d(space.getSimpleExtentNdims());
    space.getSimpleExtentDims(d.data());
    return d;
  }

  H5::DataSet open(const H5::Group& g, const std::string& group_path, const std::string& name) const {
    if (!g.nameExists(name)) fail(group_path + "/" + name, "missing");
    return g.openDataSet(name);
  }

  template <class Matrix, class Row>
  Matrix read(const H5::Group& g, const std::string& gp, const std::string& name,
              const H5::PredType& type, Eigen::Index cols) const {
    H5::DataSet ds = open(g, gp, name);
    std::vector<hsize_t> d = dims(ds);
    if (d.size() != 2 || (cols > 0 && d[1] != hsize_t(cols)))
      fail(gp + "/" + name, "unexpected shape");
    Row R(d[0], d[1]);
    if (R.size() > 0) ds.read(R.data(), type);
    return Matrix(R);
  }
  Eigen::MatrixXd matrix(const H5::Group& g, const std::string& gp, const std::string& name,
                         Eigen::Index cols = -1) const {
    Eigen::MatrixXd M = read<Eigen::MatrixXd, RowMatrixXd>(g, gp, name, H5::PredType::NATIVE_DOUBLE, cols);
    if (!M.allFinite()) fail(gp + "/" + name, "non-finite values");
    return M;
  }
  Eigen::MatrixXi imatrix(const H5::Group& g, const std::string& gp, const std::string& name,
                          Eigen::Index cols = -1) const {
    return read<Eigen::MatrixXi, RowMatrixXi>(g, gp, name, H5::PredType::NATIVE_INT, cols);
  }
  std::vector<std::string> strings(const H5::Group& g, const std::string& gp, const std::string& name) const {
    H5::DataSet ds = open(g, gp, name);
    std::vector<hsize_t> d = dims(ds);
    if (d.size() != 1) fail(gp + "/" + name, "expected a list of strings");
    H5::StrType type = ds.getStrType();
    if (type.isVariableStr()) fail(gp + "/" + name, "variable-length strings are not supported");
    const size_t len = type.getSize();
    std::vector<char> buf(d[0] * len + 1, '\0');
    if (d[0] > 0) ds.read(buf.data(), type);
    std::vector<std::string> out;
    for (hsize_t i = 0; i < d[0]; ++i) {
      const char* p = buf.data() + i * len;
      out.emplace_back(p, strnlen(p, len));
    }
    return out;
  }
  std::string attr_string(const H5::H5Object& o, const std::string& where, const std::string& name) const {
    if (!o.attrExists(name)) fail(where, "attribute '" + name + "' missing");
    H5::Attribute a = o.openAttribute(name);
    H5::StrType type = a.getStrType();
    std::string s(type.getSize(), '\0');
    a.read(type, &s[0]);
    s.resize(strnlen(s.c_str(), s.size()));
    return s;
  }
  double attr_double(const H5::H5Object& o, const std::string& where, const std::string& name) const {
    if (!o.attrExists(name)) fail(where, "attribute '" + name + "' missing");
    double v = 0;
    o.openAttribute(name).read(H5::PredType::NATIVE_DOUBLE, &v);
    return v;
  }
  std::vector<std::string> children(const H5::Group& g) const {
    std::vector<std::string> out;
    for (hsize_t i = 0; i < g.getNumObjs(); ++i) out.push_back(g.getObjnameByIdx(i));
    return out;
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
  H5::Exception::dontPrint();
  const std::string tmp = temp_path_for(path);
  try {
    {
      H5::H5File file(tmp, H5F_ACC_TRUNC);
      H5::Group root = file.openGroup("/");
      write_attr(root, "format", std::string(kFormat));
      write_attr(root, "version", kVersion);
      write_attr(root, "density", data.density);
      write_attr(root, "config", data.config_yaml);
      H5::Group levels = file.createGroup("/levels");
      Eigen::MatrixXi t(data.level_triangles.size(), 1);
      for (size_t k = 0; k < data.level_triangles.size(); ++k) t(k, 0) = data.level_triangles[k];
      write_matrix(levels, "triangles", t);
      H5::Group bodies = file.createGroup("/bodies");
      for (const BodyRecord& rec : data.bodies) {
        const Body& b = rec.body;
        H5::Group g = bodies.createGroup(b.name);
        write_mesh_group(g, b.mesh, b.weights);
        H5::Group sk = g.createGroup("skeleton");
        write_skeleton(sk, b.skeleton, b.bind);
        H5::Group garments = g.createGroup("garments");
        for (const GarmentLevels& gl : rec.garments) {
          H5::Group gg = garments.createGroup(gl.name);
          for (size_t k = 0; k < gl.levels.size(); ++k) {
            const Garment& gar = gl.levels[k];
            H5::Group lg = gg.createGroup("level_" + std::to_string(k + 1));
            write_mesh_group(lg, gar.mesh, gar.weights);
            write_matrix(lg, "masses", Eigen::MatrixXd(vertex_masses(gar.mesh.V, gar.mesh.F, data.density)));
            write_attr(lg, "target_triangles", k < data.level_triangles.size() ? data.level_triangles[k] : 0);
            write_attr(lg, "mean_edge_length", mean_edge_length(gar.mesh.V, gar.mesh.F));
          }
        }
      }
      H5::Group motions = file.createGroup("/motions");
      std::vector<std::string> train, test, heldout;
      for (const MotionRecord& m : data.motions) {
        H5::Group g = motions.createGroup(m.name);
        write_attr(g, "body", m.body);
        write_attr(g, "source", m.source);
        write_attr(g, "split", m.split);
        write_attr(g, "fps", m.motion.fps);
        const int T = m.motion.num_frames();
        const int J = T > 0 ? static_cast<int>(m.motion.frames[0].rotations.size()) : 0;
        Eigen::MatrixXd root(T, 3), rot(T, 4 * J);
        for (int f = 0; f < T; ++f) {
          root.row(f) = m.motion.frames[f].root.transpose();
          Eigen::MatrixXd q = quaternions(m.motion.frames[f].rotations);
          for (int j = 0; j < J; ++j) rot.block(f, 4 * j, 1, 4) = q.row(j);
        }
        write_matrix(g, "root_translation", root);
        RowMatrixXd R = rot;
        write_array(g, "rotations", R.data(), H5::PredType::NATIVE_DOUBLE,
                    {hsize_t(T), hsize_t(J), 4});
        (m.split == "test" ? test : m.split == "heldout" ? heldout : train).push_back(m.name);
      }
      H5::Group split = file.createGroup("/split");
      write_strings(split, "train", train);
      write_strings(split, "test", test);
      if (!heldout.empty()) write_strings(split, "heldout", heldout);
    }
    commit_file(tmp, path);
  } catch (const H5::Exception& e) {
    std::remove(tmp.c_str());
    fail_file(path, "cannot write dataset: " + e.getDetailMsg());
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
}

Dataset read_dataset(const std::string& path) {
  H5::Exception::dontPrint();
  Reader r{path};
  {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) fail_file(path, "cannot open dataset file");
    std::fclose(f);
  }
  Dataset data;
  try {
    if (!H5::H5File::isHdf5(path)) fail_file(path, "not an HDF5 file (corrupt or truncated?)");
    H5::H5File file(path, H5F_ACC_RDONLY);
    H5::Group root = file.openGroup("/");
    if (!root.attrExists("format") || r.attr_string(root, "/", "format") != kFormat)
      fail_file(path, "not a pb4u dataset (no format attribute 'pb4u-dataset')");
    data.density = r.attr_double(root, "/", "density");
    data.config_yaml = r.attr_string(root, "/", "config");
    if (!file.nameExists("levels")) r.fail("/levels", "missing");
    const Eigen::MatrixXi t = r.imatrix(file.openGroup("/levels"), "/levels", "triangles", 1);
    data.level_triangles.assign(t.data(), t.data() + t.size());
    if (!file.nameExists("bodies")) r.fail("/bodies", "missing");
    H5::Group bodies = file.openGroup("/bodies");
    for (const std::string& name : r.children(bodies)) {
      const std::string gp = "/bodies/" + name;
      H5::Group g = bodies.openGroup(name);
      BodyRecord rec;
      Body& b = rec.body;
      b.name = name;
      b.mesh.V = r.matrix(g, gp, "vertices", 3);
      b.mesh.F = r.imatrix(g, gp, "faces", 3);
      b.weights = r.read<Eigen::MatrixXd, RowMatrixXd>(g, gp, "skin_weights", H5::PredType::NATIVE_DOUBLE, -1);
      r.check_mesh(b.mesh, b.weights, gp);
      if (!g.nameExists("skeleton")) r.fail(gp + "/skeleton", "missing");
      H5::Group sk = g.openGroup("skeleton");
      const std::string sp = gp + "/skeleton";
      b.skeleton.names = r.strings(sk, sp, "joint_names");
      const Eigen::MatrixXi parents = r.imatrix(sk, sp, "parents", 1);
      b.skeleton.parents.assign(parents.data(), parents.data() + parents.size());
      b.skeleton.offsets = r.matrix(sk, sp, "offsets", 3);
      validate_skeleton(b.skeleton, path + ": " + sp);
      const int J = b.skeleton.num_joints();
      if (b.weights.cols() != J) r.fail(gp + "/skin_weights", "column count differs from joints");
      const Eigen::MatrixXd bind = r.matrix(sk, sp, "bind_rotations", 4);
      if (bind.rows() != J) r.fail(sp + "/bind_rotations", "one row per joint expected");
      b.bind.rotations = r.quats(bind);
      b.bind.root = r.matrix(sk, sp, "bind_root", 3).row(0).transpose();
      if (g.nameExists("garments")) {
        H5::Group garments = g.openGroup("garments");
        for (const std::string& gname : r.children(garments)) {
          H5::Group gg = garments.openGroup(gname);
          GarmentLevels gl;
          gl.name = gname;
          for (size_t k = 1; gg.nameExists("level_" + std::to_string(k)); ++k) {
            const std::string lp = gp + "/garments/" + gname + "/level_" + std::to_string(k);
            H5::Group lg = gg.openGroup("level_" + std::to_string(k));
            Garment gar;
            gar.name = gname;
            gar.mesh.V = r.matrix(lg, lp, "vertices", 3);
            gar.mesh.F = r.imatrix(lg, lp, "faces", 3);
            gar.weights = r.read<Eigen::MatrixXd, RowMatrixXd>(lg, lp, "skin_weights",
                                                               H5::PredType::NATIVE_DOUBLE, J);
            r.check_mesh(gar.mesh, gar.weights, lp);
            gl.levels.push_back(std::move(gar));
          }
          rec.garments.push_back(std::move(gl));
        }
      }
      data.bodies.push_back(std::move(rec));
    }
    if (file.nameExists("motions")) {
      H5::Group motions = file.openGroup("/motions");
      for (const std::string& name : r.children(motions)) {
        const std::string mp = "/motions/" + name;
        H5::Group g = motions.openGroup(name);
        MotionRecord m;
        m.name = name;
        m.body = r.attr_string(g, mp, "body");
        m.source = r.attr_string(g, mp, "source");
        m.split = r.attr_string(g, mp, "split");
        m.motion.fps = r.attr_double(g, mp, "fps");
        const BodyRecord* body = data.find_body(m.body);
        if (!body) r.fail(mp, "body '" + m.body + "' is not in the file");
        const int J = body->body.skeleton.num_joints();
        const Eigen::MatrixXd root = r.matrix(g, mp, "root_translation", 3);
        H5::DataSet ds = r.open(g, mp, "rotations");
        std::vector<hsize_t> d = r.dims(ds);
        if (d.size() != 3 || d[0] != hsize_t(root.rows()) || d[1] != hsize_t(J) || d[2] != 4)
          r.fail(mp + "/rotations", "expected frames x joints x 4");
        RowMatrixXd rot(d[0], 4 * J);
        if (rot.size() > 0) ds.read(rot.data(), H5::PredType::NATIVE_DOUBLE);
        if (!rot.allFinite()) r.fail(mp + "/rotations", "non-finite values");
        for (Eigen::Index f = 0; f < root.rows(); ++f) {
          Pose p;
          p.root = root.row(f).transpose();
          p.rotations = r.quats(Eigen::Map<RowMatrixXd>(rot.row(f).data(), J, 4));
          m.motion.frames.push_back(std::move(p));
        }
        data.motions.push_back(std::move(m));
      }
    }
  } catch (const H5::Exception& e) {
    fail_file(path, "corrupt or truncated dataset: " + e.getDetailMsg());
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

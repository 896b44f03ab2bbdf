#include "pb4u/io/usd_cache.h"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <initializer_list>
#include <sstream>

#include "pb4u/mesh/clean.h"
#include "pb4u/util/atomic_file.h"
#include "pb4u/util/error.h"

namespace pb4u {

namespace {

constexpr char kUsdRootPrim[] = "pb4u";

bool usda_one_of(const std::string& word, std::initializer_list<const char*> words) {
  for (const char* w : words)
    if (word == w) return true;
  return false;
}

// ---- writing ----

// A position as USD's point3f: the float32 nearest to x, printed so that it reads back exactly.
std::string usd_float(double x) { return fmt::format("{:.9g}", static_cast<float>(x)); }

std::string usd_vec3(double x, double y, double z) {
  return "(" + usd_float(x) + ", " + usd_float(y) + ", " + usd_float(z) + ")";
}

void write_usd_mesh(std::ostream& out, const UsdMeshSequence& mesh, double start) {
  out << "    def Mesh \"" << mesh.name << "\"\n    {\n";
  out << "        uniform token subdivisionScheme = \"none\"\n";
  out << "        uniform token orientation = \"rightHanded\"\n";
  out << "        uniform bool doubleSided = 1\n";
  out << "        int[] faceVertexCounts = [";
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) out << (f ? ", 3" : "3");
  out << "]\n        int[] faceVertexIndices = [";
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) out << (f || k ? ", " : "") << mesh.faces(f, k);
  out << "]\n";
  const Eigen::Vector3d& c = mesh.display_color;
  out << "        color3f[] primvars:displayColor = [" << usd_vec3(c.x(), c.y(), c.z())
      << "] (\n            interpolation = \"constant\"\n        )\n";
  out << "        float3[] extent.timeSamples = {\n";
  for (size_t t = 0; t < mesh.frames.size(); ++t) {
    const Eigen::MatrixXd& x = mesh.frames[t];
    const Eigen::RowVector3d lo = x.colwise().minCoeff(), hi = x.colwise().maxCoeff();
    out << "            " << fmt::format("{:g}", start + double(t)) << ": ["
        << usd_vec3(lo.x(), lo.y(), lo.z()) << ", " << usd_vec3(hi.x(), hi.y(), hi.z()) << "],\n";
  }
  out << "        }\n        point3f[] points.timeSamples = {\n";
  for (size_t t = 0; t < mesh.frames.size(); ++t) {
    const Eigen::MatrixXd& x = mesh.frames[t];
    out << "            " << fmt::format("{:g}", start + double(t)) << ": [";
    for (Eigen::Index v = 0; v < x.rows(); ++v) out << (v ? ", " : "") << usd_vec3(x(v, 0), x(v, 1), x(v, 2));
    out << "],\n";
  }
  out << "        }\n    }\n";
}

// ---- reading: a tokenizer and a parser for the parts of USD's text grammar a layer of meshes uses ----

struct UsdaToken {
  enum Kind { End, Punct, Number, String, Word, Path, Asset } kind = End;
  std::string text;
  int line = 0;
};

class UsdaLexer {
 public:
  UsdaLexer(std::string path, std::string text) : path_(std::move(path)), text_(std::move(text)) {
    if (text_.rfind("#usda ", 0) != 0) fail_file(path_, "not a USD text file (it does not start with '#usda 1.0')");
    pos_ = text_.find('\n');  // the header line is a comment to the tokenizer
    if (pos_ == std::string::npos) pos_ = text_.size();
    advance();
  }

  const UsdaToken& peek() const { return token_; }
  UsdaToken take() {
    UsdaToken t = token_;
    advance();
    return t;
  }
  bool at(const char* punct) const { return token_.kind == UsdaToken::Punct && token_.text == punct; }
  bool accept(const char* punct) {
    if (!at(punct)) return false;
    advance();
    return true;
  }
  void expect(const char* punct) {
    if (!accept(punct)) fail(std::string("expected '") + punct + "'");
  }
  std::string expect_word() {
    if (token_.kind != UsdaToken::Word) fail("expected a name");
    return take().text;
  }
  [[noreturn]] void fail(const std::string& what) const {
    const std::string found = token_.kind == UsdaToken::End ? "the end of the file" : "'" + token_.text + "'";
    fail_file(path_, fmt::format("line {}: {}, found {}", token_.line, what, found));
  }
  // One number token in flat array parsing (the hot path of a cache's points).
  double number() {
    if (token_.kind == UsdaToken::Number) return std::strtod(take().text.c_str(), nullptr);
    if (token_.kind == UsdaToken::Word && (token_.text == "inf" || token_.text == "nan" || token_.text == "-inf"))
      return std::strtod(take().text.c_str(), nullptr);
    fail("expected a number");
  }

 private:
  static bool word_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == ':' || c == '.'; }

  void advance() {
    for (;;) {  // whitespace and comments
      while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) {
        if (text_[pos_] == '\n') ++line_;
        ++pos_;
      }
      if (pos_ < text_.size() && text_[pos_] == '#') {
        while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
        continue;
      }
      break;
    }
    token_ = UsdaToken{};
    token_.line = line_;
    if (pos_ >= text_.size()) return;
    const char c = text_[pos_];
    const size_t start = pos_;
    if (c == '"' || c == '\'') {
      const bool triple = text_.compare(pos_, 3, std::string(3, c)) == 0;
      const std::string close = triple ? std::string(3, c) : std::string(1, c);
      pos_ += close.size();
      std::string value;
      for (;;) {
        if (pos_ >= text_.size()) fail_file(path_, fmt::format("line {}: a string is not closed", token_.line));
        if (text_.compare(pos_, close.size(), close) == 0) break;
        if (text_[pos_] == '\n') {
          if (!triple) fail_file(path_, fmt::format("line {}: a string is not closed", token_.line));
          ++line_;
        }
        if (text_[pos_] == '\\' && pos_ + 1 < text_.size()) ++pos_;
        value += text_[pos_++];
      }
      pos_ += close.size();
      token_.kind = UsdaToken::String;
      token_.text = std::move(value);
    } else if (c == '<' || c == '@') {
      const char close = c == '<' ? '>' : '@';
      const size_t end = text_.find(close, pos_ + 1);
      if (end == std::string::npos) fail_file(path_, fmt::format("line {}: '{}' is not closed", token_.line, c));
      token_.kind = c == '<' ? UsdaToken::Path : UsdaToken::Asset;
      token_.text = text_.substr(pos_ + 1, end - pos_ - 1);
      pos_ = end + 1;
    } else if (std::isdigit(static_cast<unsigned char>(c)) || ((c == '-' || c == '+' || c == '.') && pos_ + 1 < text_.size() &&
                                                               (std::isdigit(static_cast<unsigned char>(text_[pos_ + 1])) ||
                                                                text_[pos_ + 1] == '.'))) {
      ++pos_;
      while (pos_ < text_.size() && (std::isdigit(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '.' ||
                                     text_[pos_] == 'e' || text_[pos_] == 'E' ||
                                     ((text_[pos_] == '-' || text_[pos_] == '+') &&
                                      (text_[pos_ - 1] == 'e' || text_[pos_ - 1] == 'E'))))
        ++pos_;
      token_.kind = UsdaToken::Number;
      token_.text = text_.substr(start, pos_ - start);
    } else if (c == '-' && text_.compare(pos_, 4, "-inf") == 0) {
      pos_ += 4;
      token_.kind = UsdaToken::Word;
      token_.text = "-inf";
    } else if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      while (pos_ < text_.size() && word_char(text_[pos_])) ++pos_;
      token_.kind = UsdaToken::Word;
      token_.text = text_.substr(start, pos_ - start);
    } else if (std::string("()[]{},=:;").find(c) != std::string::npos) {
      ++pos_;
      token_.kind = UsdaToken::Punct;
      token_.text = std::string(1, c);
    } else {
      fail_file(path_, fmt::format("line {}: unexpected character '{}'", token_.line, c));
    }
  }

  std::string path_, text_;
  size_t pos_ = 0;
  int line_ = 1;
  UsdaToken token_;
};

// A parsed value: a scalar (number or text), or a list. Lists of numbers and of tuples of
// numbers (the bulk of a cache) are kept flat in `numbers`, `width` numbers per element.
struct UsdaValue {
  enum Kind { Scalar, NumberList, List, TimeSamples, Dictionary } kind = Scalar;
  bool is_number = false;
  double number = 0;
  std::string text;
  std::vector<double> numbers;
  int width = 1;
  std::vector<UsdaValue> items;
  std::vector<double> times;  // TimeSamples: items[i] at times[i]
};

class UsdaParser {
 public:
  UsdaParser(const std::string& path, std::string text) : path_(path), lex_(path, std::move(text)) {}

  UsdCache parse() {
    if (lex_.at("(")) layer_metadata();
    while (lex_.peek().kind != UsdaToken::End) prim("");
    UsdCache cache;
    cache.fps = time_codes_per_second_;
    bool first_time = true;
    for (RawMesh& raw : meshes_) cache.meshes.push_back(finish_mesh(raw, &cache.start_time_code, &first_time));
    return cache;
  }

 private:
  struct RawMesh {
    std::string name, prim_path;
    int line = 0;
    UsdaValue counts, indices, points, points_samples;
    bool has_points = false, has_samples = false;
    bool points_float32 = true;  // point3f (USD's points type) and float3: values are float32
  };

  // ( key = value ... ): the layer's; only the ones that set units and time are kept.
  void layer_metadata() {
    metadata([&](const std::string& key, const UsdaValue& v) {
      if (key == "metersPerUnit") meters_per_unit_ = scalar_number(v, key);
      else if (key == "upAxis") up_axis_ = v.text;
      else if (key == "timeCodesPerSecond") time_codes_per_second_ = scalar_number(v, key);
    });
    if (!(meters_per_unit_ > 0)) fail_file(path_, "metersPerUnit must be positive");
    if (!(time_codes_per_second_ > 0)) fail_file(path_, "timeCodesPerSecond must be positive");
    if (up_axis_ != "Y" && up_axis_ != "Z") fail_file(path_, "upAxis must be \"Y\" or \"Z\", got \"" + up_axis_ + "\"");
  }

  template <class OnEntry>
  void metadata(OnEntry&& on_entry) {
    lex_.expect("(");
    while (!lex_.accept(")")) {
      if (lex_.accept(";")) continue;
      if (lex_.peek().kind == UsdaToken::String) {  // a bare string is the doc
        lex_.take();
        continue;
      }
      std::string key = lex_.expect_word();
      if (usda_one_of(key, {"prepend", "append", "add", "delete", "reorder"})) key = lex_.expect_word();  // list edits
      if (lex_.accept("=")) on_entry(key, value());
    }
  }

  // def|over|class [Type] "name" [( metadata )] { properties and child prims }
  void prim(const std::string& parent) {
    const UsdaToken spec = lex_.peek();
    if (spec.kind != UsdaToken::Word || !usda_one_of(spec.text, {"def", "over", "class"}))
      lex_.fail("expected a prim ('def', 'over' or 'class')");
    lex_.take();
    std::string type;
    if (lex_.peek().kind == UsdaToken::Word) type = lex_.take().text;
    if (lex_.peek().kind != UsdaToken::String) lex_.fail("expected the prim's name in quotes");
    const std::string name = lex_.take().text;
    if (lex_.at("(")) metadata([](const std::string&, const UsdaValue&) {});
    lex_.expect("{");
    const size_t slot = meshes_.size();  // a Mesh goes before the meshes below it: file order
    RawMesh mesh;
    mesh.name = name;
    mesh.prim_path = parent + "/" + name;
    mesh.line = spec.line;
    while (!lex_.accept("}")) {
      const UsdaToken& t = lex_.peek();
      if (t.kind == UsdaToken::Word && usda_one_of(t.text, {"def", "over", "class"})) {
        prim(mesh.prim_path);
      } else if (t.kind == UsdaToken::Word && t.text == "variantSet") {
        lex_.fail("variant sets are not read");
      } else {
        property(&mesh);
      }
    }
    if (type == "Mesh") meshes_.insert(meshes_.begin() + static_cast<std::ptrdiff_t>(slot), std::move(mesh));
  }

  // [uniform|custom|varying|config]... type[[]] name[.timeSamples|.connect|.spline] [= value] [( metadata )]
  // or rel name [= targets] [( metadata )].
  void property(RawMesh* mesh) {
    while (lex_.peek().kind == UsdaToken::Word &&
           usda_one_of(lex_.peek().text,
                       {"uniform", "custom", "varying", "config", "prepend", "append", "delete", "add", "reorder"}))
      lex_.take();
    const std::string type = lex_.expect_word();
    if (lex_.accept("[")) lex_.expect("]");
    // point3f, vector3f, float3 (float32) and their half-float forms; point3d stays double.
    const bool float32 = type.back() == 'f' || type.back() == 'h' || type.rfind("float", 0) == 0 ||
                         type.rfind("half", 0) == 0;
    const std::string name = type == "rel" && lex_.peek().kind != UsdaToken::Word ? "" : lex_.expect_word();
    UsdaValue v;
    const bool assigned = lex_.accept("=");
    if (assigned) v = value();
    if (lex_.at("(")) metadata([](const std::string&, const UsdaValue&) {});
    if (!assigned) return;
    if (name == "faceVertexCounts") mesh->counts = std::move(v);
    else if (name == "faceVertexIndices") mesh->indices = std::move(v);
    else if (name == "points") mesh->points = std::move(v), mesh->has_points = true, mesh->points_float32 = float32;
    else if (name == "points.timeSamples")
      mesh->points_samples = std::move(v), mesh->has_samples = true, mesh->points_float32 = float32;
  }

  UsdaValue value() {
    UsdaValue v;
    const UsdaToken& t = lex_.peek();
    if (t.kind == UsdaToken::Number) {
      v.is_number = true;
      v.number = lex_.number();
    } else if (t.kind == UsdaToken::String || t.kind == UsdaToken::Word || t.kind == UsdaToken::Path ||
               t.kind == UsdaToken::Asset) {
      const bool asset = t.kind == UsdaToken::Asset;
      v.text = lex_.take().text;
      if (asset && lex_.peek().kind == UsdaToken::Path) lex_.take();  // @file@</prim>: a reference
      if (v.text == "inf" || v.text == "-inf" || v.text == "nan") v.is_number = true, v.number = std::strtod(v.text.c_str(), nullptr);
    } else if (lex_.at("[")) {
      list(&v);
    } else if (lex_.at("(")) {
      tuple(&v);
    } else if (lex_.at("{")) {
      braces(&v);
    } else {
      lex_.fail("expected a value");
    }
    return v;
  }

  // (a, b, c): numbers kept flat; anything else as items.
  void tuple(UsdaValue* v) {
    lex_.expect("(");
    v->kind = UsdaValue::NumberList;
    while (!lex_.accept(")")) {
      UsdaValue item = value();
      if (!item.is_number || v->kind != UsdaValue::NumberList) v->kind = UsdaValue::List;
      if (item.is_number) v->numbers.push_back(item.number);
      v->items.push_back(std::move(item));
      if (!lex_.at(")")) lex_.expect(",");
    }
    v->width = static_cast<int>(v->numbers.size());
    if (v->kind == UsdaValue::NumberList) v->items.clear();
  }

  // [1, 2, 3] or [(x, y, z), ...] flat; other lists as items.
  void list(UsdaValue* v) {
    lex_.expect("[");
    v->kind = UsdaValue::NumberList;
    int width = 0;
    while (!lex_.accept("]")) {
      if (lex_.peek().kind == UsdaToken::Number) {
        if (width == 0) width = 1;
        if (width != 1) lex_.fail("a list mixes numbers and tuples");
        v->numbers.push_back(lex_.number());
      } else if (lex_.at("(") && v->kind == UsdaValue::NumberList) {
        lex_.take();
        int count = 0;
        while (!lex_.accept(")")) {
          v->numbers.push_back(lex_.number());
          ++count;
          if (!lex_.at(")")) lex_.expect(",");
        }
        if (width == 0) width = count;
        if (count != width) lex_.fail(fmt::format("a tuple of {} in a list of {}-tuples", count, width));
      } else {
        if (!v->numbers.empty()) lex_.fail("a list mixes numbers and other values");
        v->kind = UsdaValue::List;
        v->items.push_back(value());
      }
      if (!lex_.at("]")) lex_.expect(",");
    }
    v->width = std::max(width, 1);
  }

  // { time: value, ... } (time samples) or { type name = value ... } (a dictionary).
  void braces(UsdaValue* v) {
    lex_.expect("{");
    v->kind = UsdaValue::Dictionary;
    while (!lex_.accept("}")) {
      if (lex_.peek().kind == UsdaToken::Number) {
        v->kind = UsdaValue::TimeSamples;
        v->times.push_back(lex_.number());
        lex_.expect(":");
        v->items.push_back(value());
        if (!lex_.at("}")) lex_.expect(",");
        continue;
      }
      if (v->kind == UsdaValue::TimeSamples) lex_.fail("expected a time code");
      lex_.expect_word();  // the entry's type
      if (lex_.accept("[")) lex_.expect("]");
      lex_.take();  // its name (a word or a string)
      lex_.expect("=");
      value();
      lex_.accept(";");
    }
  }

  double scalar_number(const UsdaValue& v, const std::string& key) const {
    if (!v.is_number) fail_file(path_, key + ": expected a number, got '" + v.text + "'");
    return v.number;
  }

  // A points value (a list of 3-tuples) as n x 3 metres, y up. Float32 values are rounded to
  // float32 as read, so that they equal the floats the writer had (as a PC2 cache's do).
  Eigen::MatrixXd to_positions(const UsdaValue& v, const RawMesh& raw, const std::string& where) const {
    if (v.kind != UsdaValue::NumberList || (v.width != 3 && !v.numbers.empty()))
      fail_file(path_, raw.prim_path + ": " + where + ": expected a list of (x, y, z)");
    const Eigen::Index n = static_cast<Eigen::Index>(v.numbers.size() / 3);
    Eigen::MatrixXd x(n, 3);
    for (Eigen::Index i = 0; i < n; ++i) {
      double p[3] = {v.numbers[3 * i], v.numbers[3 * i + 1], v.numbers[3 * i + 2]};
      if (raw.points_float32)
        for (double& c : p) c = static_cast<float>(c);
      if (up_axis_ == "Z") x.row(i) << p[0], p[2], -p[1];  // z-up (x, y, z) -> y-up (x, z, -y)
      else x.row(i) << p[0], p[1], p[2];
    }
    return meters_per_unit_ == 1.0 ? x : x * meters_per_unit_;
  }

  UsdMeshSequence finish_mesh(const RawMesh& raw, double* start, bool* first_time) const {
    const std::string where = raw.prim_path + " (line " + std::to_string(raw.line) + ")";
    UsdMeshSequence mesh;
    mesh.name = raw.name;
    if (raw.has_samples) {
      if (raw.points_samples.kind != UsdaValue::TimeSamples && !raw.points_samples.items.empty())
        fail_file(path_, where + ": points.timeSamples: expected { time: [points], ... }");
      std::vector<size_t> order(raw.points_samples.times.size());
      for (size_t i = 0; i < order.size(); ++i) order[i] = i;
      std::stable_sort(order.begin(), order.end(),
                       [&](size_t a, size_t b) { return raw.points_samples.times[a] < raw.points_samples.times[b]; });
      for (size_t i : order) {
        const double time = raw.points_samples.times[i];
        mesh.frames.push_back(to_positions(raw.points_samples.items[i], raw, "points at time " + fmt::format("{:g}", time)));
        if (*first_time) *start = time, *first_time = false;
      }
    }
    if (mesh.frames.empty() && raw.has_points) mesh.frames.push_back(to_positions(raw.points, raw, "points"));
    if (mesh.frames.empty()) fail_file(path_, where + ": the mesh has no points");
    const Eigen::Index n = mesh.frames[0].rows();
    for (size_t t = 1; t < mesh.frames.size(); ++t)
      if (mesh.frames[t].rows() != n)
        fail_file(path_, fmt::format("{}: time sample {} has {} points, the first {}", where, t, mesh.frames[t].rows(), n));
    for (const auto& x : mesh.frames)
      if (!x.allFinite()) fail_file(path_, where + ": points are not finite");
    // Faces: polygons fanned into triangles, as the OBJ and PLY readers do.
    if (raw.counts.kind != UsdaValue::NumberList || raw.indices.kind != UsdaValue::NumberList || raw.counts.width != 1 ||
        raw.indices.width != 1)
      fail_file(path_, where + ": faceVertexCounts and faceVertexIndices must be lists of integers");
    std::vector<std::vector<int>> polygons;
    size_t corner = 0;
    for (double count : raw.counts.numbers) {
      if (count < 3 || count != std::floor(count))
        fail_file(path_, where + ": faceVertexCounts holds " + fmt::format("{:g}", count) + " (a face needs 3 or more)");
      if (corner + size_t(count) > raw.indices.numbers.size())
        fail_file(path_, where + ": faceVertexCounts adds up to more than the faceVertexIndices");
      std::vector<int>& polygon = polygons.emplace_back();
      for (size_t c = corner; c < corner + size_t(count); ++c) {
        const double index = raw.indices.numbers[c];
        if (index < 0 || index >= double(n) || index != std::floor(index))
          fail_file(path_, fmt::format("{}: faceVertexIndices holds {:g}, the mesh has {} points", where, index, n));
        polygon.push_back(static_cast<int>(index));
      }
      corner += size_t(count);
    }
    if (corner != raw.indices.numbers.size())
      fail_file(path_, where + ": faceVertexCounts adds up to fewer than the faceVertexIndices");
    mesh.faces = triangulate_polygons(polygons);
    return mesh;
  }

  std::string path_;
  UsdaLexer lex_;
  double meters_per_unit_ = 1.0, time_codes_per_second_ = 24.0;  // USD's defaults
  std::string up_axis_ = "Y";
  std::vector<RawMesh> meshes_;
};

}  // namespace

void write_usd_cache(const std::string& path, const UsdCache& cache) {
  if (cache.meshes.empty()) fail_file(path, "a USD cache needs at least one mesh");
  const size_t T = cache.meshes[0].frames.size();
  if (T == 0) fail_file(path, "a USD cache needs at least one frame");
  if (!(cache.fps > 0)) fail_file(path, "the USD cache's fps must be positive");
  for (const UsdMeshSequence& m : cache.meshes) {
    if (m.frames.size() != T) fail_file(path, "USD cache meshes differ in frame count (" + m.name + ")");
    if (m.name.empty() || !std::all_of(m.name.begin(), m.name.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }) ||
        std::isdigit(static_cast<unsigned char>(m.name[0])))
      fail_file(path, "'" + m.name + "' is not a USD prim name");
    for (const Eigen::MatrixXd& x : m.frames)
      if (x.rows() != m.frames[0].rows() || x.cols() != 3)
        fail_file(path, "USD cache frames of " + m.name + " differ in vertex count");
    if (m.faces.size() && (m.faces.cols() != 3 || m.faces.minCoeff() < 0 || m.faces.maxCoeff() >= m.frames[0].rows()))
      fail_file(path, "USD cache faces of " + m.name + " index beyond its vertices");
  }
  AtomicFile file(path);
  std::ostream& out = file.stream();
  const double start = cache.start_time_code, end = start + double(T - 1);
  out << "#usda 1.0\n(\n    doc = \"pb4u cloth cache: time code t is frame t\"\n"
      << "    defaultPrim = \"" << kUsdRootPrim << "\"\n    metersPerUnit = 1\n    upAxis = \"Y\"\n"
      << fmt::format("    startTimeCode = {:g}\n    endTimeCode = {:g}\n", start, end)
      << fmt::format("    timeCodesPerSecond = {:g}\n    framesPerSecond = {:g}\n)\n\n", cache.fps, cache.fps);
  out << "def Xform \"" << kUsdRootPrim << "\" (\n    kind = \"component\"\n)\n{\n";
  for (size_t i = 0; i < cache.meshes.size(); ++i) {
    if (i) out << '\n';
    write_usd_mesh(out, cache.meshes[i], start);
  }
  out << "}\n";
  file.commit();
}

UsdCache read_usd_cache(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail_file(path, "cannot open the USD file");
  std::ostringstream text;
  text << in.rdbuf();
  if (text.str().rfind("PXR-USDC", 0) == 0)
    fail_file(path, "a binary USD (usdc) file: only USD text (.usda) is read; convert it with usdcat");
  return UsdaParser(path, text.str()).parse();
}

}  // namespace pb4u

#include "pb4u/config/config_io.h"

#include <cmath>
#include <filesystem>
#include <fstream>

#include "pb4u/util/atomic_file.h"

namespace pb4u {

namespace {
std::string number(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}
}  // namespace

Check<double> in_range(double lo, double hi) {
  return [=](const double& v) {
    return v >= lo && v <= hi ? "" : "must be in [" + number(lo) + ", " + number(hi) + "], got " + number(v);
  };
}
Check<double> positive() {
  return [](const double& v) { return v > 0 ? "" : "must be positive, got " + number(v); };
}
Check<double> non_negative() {
  return [](const double& v) { return v >= 0 ? "" : "must be >= 0, got " + number(v); };
}
Check<int> int_in_range(int lo, int hi) {
  return [=](const int& v) {
    return v >= lo && v <= hi ? ""
                              : "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                                    "], got " + std::to_string(v);
  };
}
Check<int> int_at_least(int lo) {
  return [=](const int& v) {
    return v >= lo ? "" : "must be >= " + std::to_string(lo) + ", got " + std::to_string(v);
  };
}
Check<std::string> one_of(std::vector<std::string> allowed) {
  return [allowed = std::move(allowed)](const std::string& v) {
    for (const auto& a : allowed)
      if (a == v) return std::string();
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : " | ") + a;
    return "must be one of " + list + ", got '" + v + "'";
  };
}

namespace detail {
std::string type_name_of(double) { return "a number"; }
std::string type_name_of(int) { return "an integer"; }
std::string type_name_of(bool) { return "true or false"; }
std::string type_name_of(const std::string&) { return "a string"; }
}  // namespace detail

void ConfigReader::fail(const std::string& path, const std::string& why) const {
  // Name "--set" for keys the command line overrode: the file never said that.
  bool from_set = false;
  if (overridden_)
    for (const auto& o : *overridden_)
      if (o == path || path.rfind(o + ".", 0) == 0 || o.rfind(path + ".", 0) == 0) from_set = true;
  std::string where = from_set ? "--set " + path : file_ + ": key '" + path + "'";
  throw Error(where + ": " + why);
}

void ConfigReader::finish() const {
  if (!node_.IsMap()) return;
  for (const auto& kv : node_) {
    // A YAML key may be a list, a map or null ("? :", found by config_fuzz); ours are names.
    if (!kv.first.IsScalar()) fail(prefix_ + "?", "a key must be a plain name, not a list, map or null");
    std::string key = kv.first.as<std::string>();
    if (!seen_.count(key)) {
      std::string known;
      for (const auto& k : seen_) known += (known.empty() ? "" : ", ") + k;
      fail(prefix_ + key, "unknown key (known here: " + known + ")");
    }
  }
}

void ConfigReader::read_scalar(const YAML::Node& n, const std::string& path, double& v) const {
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    fail(path, "expected a number, got '" + n.Scalar() + "'");
  }
  if (!std::isfinite(v)) fail(path, "must be finite, got '" + n.Scalar() + "'");
}
void ConfigReader::read_scalar(const YAML::Node& n, const std::string& path, int& v) const {
  try {
    v = n.as<int>();
  } catch (const YAML::Exception&) {
    fail(path, "expected an integer, got '" + n.Scalar() + "'");
  }
}
void ConfigReader::read_scalar(const YAML::Node& n, const std::string& path, bool& v) const {
  try {
    v = n.as<bool>();
  } catch (const YAML::Exception&) {
    fail(path, "expected true or false, got '" + n.Scalar() + "'");
  }
}
void ConfigReader::read_scalar(const YAML::Node& n, const std::string&, std::string& v) const {
  v = n.Scalar();
}

YAML::Node load_yaml_file(const std::string& file) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) fail_file(file, "no such config file");
  if (std::filesystem::is_directory(file, ec)) fail_file(file, "is a directory, not a config file");
  YAML::Node root;
  try {
    root = YAML::LoadFile(file);
  } catch (const YAML::Exception& e) {
    fail_file(file, "invalid YAML at line " + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  if (root.IsNull()) return YAML::Node(YAML::NodeType::Map);  // empty file: all defaults
  if (!root.IsMap()) fail_file(file, "expected a map of keys at the top level");
  return root;
}

void apply_overrides(YAML::Node& root, const std::vector<std::string>& sets,
                     std::set<std::string>* overridden) {
  for (const auto& s : sets) {
    auto eq = s.find('=');
    if (eq == std::string::npos || eq == 0)
      throw Error("--set " + s + ": expected key.path=value");
    std::string path = s.substr(0, eq), value = s.substr(eq + 1);
    std::vector<std::string> keys;
    for (size_t start = 0;;) {
      size_t dot = path.find('.', start);
      keys.push_back(path.substr(start, dot - start));
      if (dot == std::string::npos) break;
      start = dot + 1;
    }
    // yaml-cpp's operator[] on a non-const node creates missing children; walk by value copies
    // of the handles (they alias the same tree).
    YAML::Node node = root;
    for (size_t i = 0; i + 1 < keys.size(); ++i) {
      if (keys[i].empty()) throw Error("--set " + s + ": empty key in path");
      YAML::Node child = node[keys[i]];
      if (!child || child.IsNull() || !child.IsMap()) node[keys[i]] = YAML::Node(YAML::NodeType::Map);
      node.reset(node[keys[i]]);
    }
    YAML::Node parsed;
    try {
      parsed = YAML::Load(value);
    } catch (const YAML::Exception& e) {
      throw Error("--set " + path + ": invalid value '" + value + "'");
    }
    node[keys.back()] = parsed;
    if (overridden) overridden->insert(path);
  }
}

void write_text_file(const std::string& path, const std::string& text) {
  AtomicFile file(path);
  file.stream() << text;
  file.commit();
}

}  // namespace pb4u

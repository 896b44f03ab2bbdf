#pragma once
// Typed YAML configs. A config section is a plain struct with defaults and a
// `visit` member that names each field once:
//
//   struct Material {
//     double density = 0.20022;                  // kg/m^2
//     template <class V> void visit(V& v) { v("density", density, positive()); }
//   };
//
// The same `visit` drives reading (type and range checks, unknown keys rejected) and
// writing (the effective config saved next to every output), so the two never drift.
// Errors are pb4u::Error naming the file (or "--set") and the full key path.
#include <yaml-cpp/yaml.h>

#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "pb4u/util/error.h"

namespace pb4u {

template <class T>
using Check = std::function<std::string(const T&)>;  // "" when valid, else the reason

Check<double> in_range(double lo, double hi);
Check<double> positive();
Check<double> non_negative();
Check<int> int_in_range(int lo, int hi);
Check<int> int_at_least(int lo);
Check<std::string> one_of(std::vector<std::string> allowed);

namespace detail {
struct AnyVisitor {};
template <class T, class = void>
struct is_section : std::false_type {};
template <class T>
struct is_section<T, std::void_t<decltype(std::declval<T&>().visit(std::declval<AnyVisitor&>()))>>
    : std::true_type {};
template <class T>
struct is_vector : std::false_type {};
template <class T>
struct is_vector<std::vector<T>> : std::true_type {};

std::string type_name_of(double);
std::string type_name_of(int);
std::string type_name_of(bool);
std::string type_name_of(const std::string&);
}  // namespace detail

// Reads a YAML map into a section, checking types, ranges and unknown keys.
class ConfigReader {
 public:
  ConfigReader(YAML::Node node, std::string file, std::string prefix,
               const std::set<std::string>* overridden)
      : node_(std::move(node)), file_(std::move(file)), prefix_(std::move(prefix)),
        overridden_(overridden) {}

  template <class T>
  void operator()(const char* key, T& value, Check<T> check = {}) {
    seen_.insert(key);
    const std::string path = prefix_ + key;
    YAML::Node child = node_[key];
    if (!child || child.IsNull()) return;  // keep the default
    read_value(child, path, value);
    if (check) {
      std::string why = check(value);
      if (!why.empty()) fail(path, why);
    }
  }

  // Rejects keys the section did not visit.
  void finish() const;

  [[noreturn]] void fail(const std::string& path, const std::string& why) const;

 private:
  template <class T>
  void read_value(const YAML::Node& n, const std::string& path, T& value) {
    if constexpr (is_section_v<T>) {
      if (!n.IsMap()) fail(path, "expected a map of keys");
      ConfigReader sub(n, file_, path + ".", overridden_);
      value.visit(sub);
      sub.finish();
    } else if constexpr (detail::is_vector<T>::value) {
      if (!n.IsSequence()) fail(path, "expected a list");
      T out(n.size());
      for (size_t i = 0; i < n.size(); ++i)
        read_value(n[i], path + "[" + std::to_string(i) + "]", out[i]);
      value = std::move(out);
    } else {
      if (!n.IsScalar()) fail(path, "expected " + detail::type_name_of(value));
      read_scalar(n, path, value);
    }
  }
  void read_scalar(const YAML::Node& n, const std::string& path, double& v) const;
  void read_scalar(const YAML::Node& n, const std::string& path, int& v) const;
  void read_scalar(const YAML::Node& n, const std::string& path, bool& v) const;
  void read_scalar(const YAML::Node& n, const std::string& path, std::string& v) const;

  template <class T>
  static constexpr bool is_section_v = detail::is_section<T>::value;

  YAML::Node node_;
  std::string file_, prefix_;
  const std::set<std::string>* overridden_;
  std::set<std::string> seen_;
};

// Emits a section as YAML.
class ConfigWriter {
 public:
  explicit ConfigWriter(YAML::Emitter& out) : out_(out) {}
  template <class T>
  void operator()(const char* key, const T& value, Check<T> = {}) {
    out_ << YAML::Key << key << YAML::Value;
    write_value(value);
  }

 private:
  template <class T>
  void write_value(const T& value) {
    if constexpr (detail::is_section<T>::value) {
      out_ << YAML::BeginMap;
      const_cast<T&>(value).visit(*this);
      out_ << YAML::EndMap;
    } else if constexpr (detail::is_vector<T>::value) {
      out_ << YAML::Flow << YAML::BeginSeq;
      for (const auto& x : value) write_value(x);
      out_ << YAML::EndSeq;
    } else if constexpr (std::is_same_v<T, double>) {
      std::ostringstream s;
      s.precision(10);
      s << value;
      out_ << s.str();
    } else {
      out_ << value;
    }
  }
  YAML::Emitter& out_;
};

// Parses the YAML file (if non-empty), applies "a.b=v" overrides and reads the result into
// `config`, whose defaults stand for absent keys.
YAML::Node load_yaml_file(const std::string& file);
void apply_overrides(YAML::Node& root, const std::vector<std::string>& sets,
                     std::set<std::string>* overridden);

template <class Config>
Config load_config(const std::string& file, const std::vector<std::string>& sets = {}) {
  YAML::Node root = file.empty() ? YAML::Node(YAML::NodeType::Map) : load_yaml_file(file);
  std::set<std::string> overridden;
  apply_overrides(root, sets, &overridden);
  Config config;
  ConfigReader reader(root, file.empty() ? "<defaults>" : file, "", &overridden);
  config.visit(reader);
  reader.finish();
  return config;
}

template <class Config>
std::string config_to_yaml(const Config& config) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  ConfigWriter writer(out);
  const_cast<Config&>(config).visit(writer);
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

// Writes the effective config atomically (e.g. "<out>/config.yaml").
void write_text_file(const std::string& path, const std::string& text);

template <class Config>
void save_config(const Config& config, const std::string& path) {
  write_text_file(path, config_to_yaml(config));
}

}  // namespace pb4u

#include "pb4u/model/model_file.h"

#include <spdlog/fmt/fmt.h>
#include <yaml-cpp/yaml.h>

#include <fstream>
#include <map>
#include <sstream>

#include "pb4u/io/hdf5_file.h"
#include "pb4u/io/module_hdf5.h"
#include "pb4u/model/checkpoint.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace {

// The `model` section of a YAML document (`section_key` empty: the document is the section).
ModelConfig parse_model_config(const std::string& yaml, const std::string& section_key,
                               const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::Exception& e) {
    fail_file(path, "the stored model config is not valid YAML (" + std::string(e.what()) + ")");
  }
  YAML::Node node = section_key.empty() ? root : root[section_key];
  if (!node || !node.IsMap()) fail_file(path, "no model config stored in the file");
  ModelConfig config;
  ConfigReader reader(node, path, section_key.empty() ? "model." : section_key + ".", nullptr);
  config.visit(reader);
  reader.finish();
  validate_model_config(config, path + ": model");
  return config;
}

double attribute_number(const std::map<std::string, std::string>& attrs, const std::string& key,
                        const std::string& path) {
  auto it = attrs.find(key);
  if (it == attrs.end()) fail_file(path, "export lacks the '" + key + "' attribute");
  try {
    size_t used = 0;
    double v = std::stod(it->second, &used);
    if (used != it->second.size()) throw std::invalid_argument(key);
    return v;
  } catch (const std::exception&) {
    fail_file(path, "attribute '" + key + "' is not a number ('" + it->second + "')");
  }
}

ModelFile load_export(const std::string& path) {
  const auto attrs = read_hdf5_attributes(path);
  auto format = attrs.find("format");
  if (format == attrs.end() || format->second != kExportFormat)
    fail_file(path, "not a pb4u model export (no format attribute '" + std::string(kExportFormat) + "')");
  const double version = attribute_number(attrs, "format_version", path);
  if (version != double(kExportFormatVersion))
    fail_file(path, "export format version " + attrs.at("format_version") + " is not supported (expected " +
                        std::to_string(kExportFormatVersion) + ")");
  auto yaml = attrs.find("model_config");
  if (yaml == attrs.end()) fail_file(path, "export lacks the 'model_config' attribute");
  ModelFile m;
  m.path = path;
  m.source = "export";
  m.config = parse_model_config(yaml->second, "", path);
  m.config_yaml = config_to_yaml(m.config);
  m.step = static_cast<int64_t>(attribute_number(attrs, "step", path));
  m.model = Pb4uNet(m.config);
  load_module_hdf5(path, *m.model);
  // The attributes are for readers without pb4u; the buffers are what the model uses. A file
  // whose two disagree has been edited by hand.
  const double lbar = attribute_number(attrs, "lbar_base", path);
  if (std::abs(lbar - m.model->mean_edge_length_base()) > 1e-12 * std::max(1.0, lbar))
    fail_file(path, "attribute lbar_base disagrees with the stored calibration buffer");
  return m;
}

ModelFile load_training_checkpoint(const std::string& path) {
  const CheckpointMeta meta = read_checkpoint_meta(path);
  ModelFile m;
  m.path = path;
  m.source = "training checkpoint";
  m.step = meta.step;
  m.config = parse_model_config(meta.config_yaml, "model", path);
  m.config_yaml = config_to_yaml(m.config);
  m.model = Pb4uNet(m.config);
  load_checkpoint(path, *m.model, nullptr);
  return m;
}

}  // namespace

bool is_model_export(const std::string& path) {
  if (!is_hdf5_file(path)) return false;
  try {
    auto attrs = read_hdf5_attributes(path);
    auto it = attrs.find("format");
    return it != attrs.end() && it->second == kExportFormat;
  } catch (const Error&) {
    return false;
  }
}

ModelFile load_model_file(const std::string& path) {
  if (!std::ifstream(path).good()) fail_file(path, "cannot open the model file");
  ModelFile m = is_hdf5_file(path) ? load_export(path) : load_training_checkpoint(path);
  if (!m.model->calibrated()) fail_file(path, "the model was never calibrated (Lbar_base = 0)");
  m.model->eval();
  return m;
}

void set_inference_switches(ModelFile& model, const std::vector<std::string>& assignments) {
  if (assignments.empty()) return;
  YAML::Node node = YAML::Load(model.config_yaml);
  for (const std::string& a : assignments) {
    const auto eq = a.find('=');
    std::string key = a.substr(0, eq);
    if (key.rfind("model.", 0) == 0) key = key.substr(6);
    if (eq == std::string::npos || eq + 1 == a.size())
      throw Error("--set " + a + ": expected KEY=VALUE");
    if (key != "update_scaling" && key != "smooth_distance" && key != "propagation_control" &&
        key != "contact_projection" && key != "strain_limit" && key != "refine_iterations" &&
        key != "refine_tolerance_mm" && key != "refine_contact" && key != "refine_strain_limit")
      throw Error("--set " + a + ": only update_scaling, smooth_distance, propagation_control, "
                  "contact_projection, strain_limit, refine_iterations, refine_tolerance_mm, refine_contact and "
                  "refine_strain_limit "
                  "can change without retraining (the weights stay as trained)");
    node[key] = a.substr(eq + 1);
  }
  std::stringstream yaml;
  yaml << node;
  model.config = parse_model_config(yaml.str(), "", "--set");
  model.config_yaml = config_to_yaml(model.config);
  model.model->config = model.config;
}

void export_model_file(const ModelFile& model, const std::string& out) {
  std::map<std::string, std::string> attrs;
  auto number = [](double v) {
    char s[64];
    std::snprintf(s, sizeof s, "%.17g", v);
    return std::string(s);
  };
  attrs["format"] = kExportFormat;
  attrs["format_version"] = std::to_string(kExportFormatVersion);
  attrs["model_config"] = model.config_yaml;
  attrs["method"] = method_name(model.config);
  attrs["lbar_base"] = number(model.model->mean_edge_length_base());
  attrs["propagation_distance"] = number(model.model->propagation_distance());
  attrs["k_base"] = std::to_string(model.config.k_base);
  attrs["step"] = std::to_string(model.step);
  attrs["parameter_count"] = std::to_string(parameter_count(*model.model));
  attrs["source"] = model.path;
  save_module_hdf5(out, *model.model, attrs);
}

namespace {

std::string network_name(const ModelConfig& config) {
  // The paper's MGN, HOOD and CCRAFT are fixed-depth and unscaled; with update scaling on each is
  // another model.
  if (config.is_hood()) return config.update_scaling_on() ? "HOOD w/ US" : "HOOD";
  if (config.is_ccraft()) return config.update_scaling_on() ? "CCRAFT (stage 1) w/ US" : "CCRAFT (stage 1)";
  // Rebuilt from the ESLR paper (its code is not public): the name says so wherever it appears.
  if (config.is_eslr()) return config.update_scaling_on() ? "ESLR (rec.) w/ US" : "ESLR (rec.)";
  if (!config.is_pb4u()) return config.update_scaling_on() ? "MGN w/ US" : "MGN";
  const bool pc = config.propagation_control_on(), us = config.update_scaling_on();
  if (pc && us) return "Pb4U";
  if (!pc && !us) return "Pb4U w/o both";
  return pc ? "Pb4U w/o US" : "Pb4U w/o PC";
}

}  // namespace

std::string refine_label(int iterations, double tolerance_mm) {
  std::string label;
  if (iterations > 0) label += " + " + std::to_string(iterations) + " it";
  if (tolerance_mm > 0) label += fmt::format(" + to {:g} mm", tolerance_mm);
  return label;
}

std::string method_name(const ModelConfig& config) {
  std::string refine;
  if (config.refines()) {
    refine = refine_label(config.refine_iterations, config.refine_tolerance_mm);
    if (config.refine_contact == "barrier" && config.refine_strain_limit > 0) refine += " (barrier, strain barrier)";
    else if (config.refine_contact == "barrier") refine += " (barrier)";
    else if (config.refine_strain_limit > 0) refine += " (strain barrier)";
  }
  return network_name(config) + (config.contact_projection > 0 ? " + projection" : "") +
         (config.strain_limit > 0 ? " + strain limit" : "") + refine;
}

int64_t parameter_count(const torch::nn::Module& module) {
  int64_t n = 0;
  for (const auto& p : module.parameters()) n += p.numel();
  return n;
}

void print_model_summary(std::ostream& out, const ModelFile& m) {
  out << "kind: model (" << m.source << ")\n";
  out << "method: " << method_name(m.config) << "\n";
  out << "step: " << m.step << "\n";
  out << "parameters: " << parameter_count(*m.model) << "\n";
  out << "calibration: Lbar_base " << m.model->mean_edge_length_base() << " m, D "
      << m.model->propagation_distance() << " m, K_base " << m.config.k_base << "\n";
  out << "model config:\n";
  std::istringstream lines(m.config_yaml);
  for (std::string line; std::getline(lines, line);) out << "  " << line << "\n";
}

}  // namespace pb4u

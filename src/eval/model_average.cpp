#include "pb4u/eval/model_average.h"

#include <cmath>
#include <sstream>

#include "pb4u/util/error.h"

namespace pb4u {
namespace {

std::string shape_text(const torch::Tensor& t) {
  std::ostringstream s;
  s << t.sizes();
  return s.str();
}

// Every tensor of `other` has a same-named, same-shaped one in `first`, and as many.
void check_same_tensors(const torch::OrderedDict<std::string, torch::Tensor>& first,
                        const torch::OrderedDict<std::string, torch::Tensor>& other, const char* what,
                        const std::string& first_path, const std::string& other_path) {
  if (first.size() != other.size())
    throw Error(other_path + ": cannot average with " + first_path + ": " + std::to_string(other.size()) + " " +
                what + "s against " + std::to_string(first.size()));
  for (const auto& item : other) {
    const torch::Tensor* t = first.find(item.key());
    if (!t || t->sizes() != item.value().sizes())
      throw Error(other_path + ": cannot average with " + first_path + ": " + what + " '" + item.key() + "' " +
                  (t ? "has shape " + shape_text(item.value()) + " against " + shape_text(*t) : "is not in both"));
  }
}

}  // namespace

ModelFile average_models(const std::vector<ModelFile>& models, const std::vector<double>& weights) {
  if (models.empty()) throw Error("averaging: no model given");
  std::vector<double> w = weights;
  if (w.empty()) w.assign(models.size(), 1.0 / double(models.size()));
  if (w.size() != models.size())
    throw Error("--weights: " + std::to_string(w.size()) + " weights for " + std::to_string(models.size()) +
                " models; give one per --checkpoint");
  double sum = 0;
  for (double x : w) {
    if (!std::isfinite(x)) throw Error("--weights: every weight must be a finite number");
    sum += x;
  }
  if (std::abs(sum - 1.0) > 1e-6)
    throw Error("--weights: the weights sum to " + std::to_string(sum) + "; they must sum to 1");

  const ModelFile& first = models.front();
  ModelFile out = first;
  out.model = Pb4uNet(first.config);
  torch::NoGradGuard no_grad;
  auto out_params = out.model->named_parameters();
  auto out_buffers = out.model->named_buffers();
  for (auto& p : out_params) p.value().zero_();
  for (const auto& b : first.model->named_buffers()) out_buffers[b.key()].copy_(b.value());

  for (size_t i = 0; i < models.size(); ++i) {
    const ModelFile& m = models[i];
    if (m.config.is_pb4u() != first.config.is_pb4u())
      throw Error(m.path + ": cannot average with " + first.path + ": " + method_name(m.config) + " against " +
                  method_name(first.config));
    const auto params = m.model->named_parameters();
    const auto buffers = m.model->named_buffers();
    check_same_tensors(out_params, params, "parameter", first.path, m.path);
    check_same_tensors(out_buffers, buffers, "buffer", first.path, m.path);
    // Normaliser statistics and calibration are not learned: models that saw different
    // feature scales do not mix.
    for (const auto& b : buffers) {
      const torch::Tensor a = b.value().to(torch::kFloat64), ref = out_buffers[b.key()].to(torch::kFloat64);
      if (!torch::allclose(a, ref, 1e-6, 1e-12))
        throw Error(m.path + ": cannot average with " + first.path + ": buffer '" + b.key() +
                    "' differs (normaliser statistics or calibration); average checkpoints of one run after "
                    "its warm-up, or a fine-tune with the model it started from");
    }
    for (const auto& p : params) out_params[p.key()].add_(p.value().to(torch::kCPU), w[i]);
  }
  out.model->eval();
  std::ostringstream source;
  for (size_t i = 0; i < models.size(); ++i) source << (i ? " + " : "") << w[i] << " * " << models[i].path;
  out.path = source.str();
  out.source = "weight average";
  return out;
}

}  // namespace pb4u

#include "pb4u/train/init_weights.h"

#include <sstream>

#include "pb4u/model/model_file.h"
#include "pb4u/model/checkpoint.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace {

// dst <- src for tensors of the same name; every tensor of `to` must be in `from`, shaped alike.
void copy_named(const torch::OrderedDict<std::string, torch::Tensor>& from,
                const torch::OrderedDict<std::string, torch::Tensor>& to, const char* what,
                const std::string& path) {
  if (from.size() != to.size()) {
    std::ostringstream why;
    why << path << ": does not match the model: " << from.size() << " " << what << "s, the model has " << to.size();
    throw Error(why.str());
  }
  torch::NoGradGuard no_grad;
  for (const auto& item : to) {
    const torch::Tensor* src = from.find(item.key());
    if (!src) throw Error(path + ": does not match the model: no " + what + " '" + item.key() + "'");
    torch::Tensor dst = item.value();
    if (src->sizes() != dst.sizes()) {
      std::ostringstream why;
      why << path << ": does not match the model: " << what << " '" << item.key() << "' has shape " << src->sizes()
          << ", the model expects " << dst.sizes();
      throw Error(why.str());
    }
    dst.copy_(src->to(dst.device(), dst.scalar_type()));
  }
}

}  // namespace

int64_t init_weights_from(const std::string& path, torch::nn::Module& model, torch::Device device) {
  if (!is_model_export(path)) return load_checkpoint(path, model, nullptr, device).step;
  const ModelFile file = load_model_file(path);
  copy_named(file.model->named_parameters(), model.named_parameters(), "parameter", path);
  copy_named(file.model->named_buffers(), model.named_buffers(), "buffer", path);
  return file.step;
}

}  // namespace pb4u

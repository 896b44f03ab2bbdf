// The `model` config section: overrides, rejection of bad values, round trip.
#include <gtest/gtest.h>

#include "pb4u/model/model_config.h"
#include "pb4u/util/error.h"
#include "test_util.h"

namespace pb4u {
namespace {

struct Root {
  ModelConfig model;
  template <class V>
  void visit(V& v) { v("model", model); }
};

std::string error_of(const std::vector<std::string>& sets) {
  try {
    load_config<Root>("", sets);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(ModelConfig, OverridesAndRoundTrip) {
  Root r = load_config<Root>("", {"model.kind=mgn", "model.latent=32", "model.update_scaling=off",
                                  "model.material_ranges.mu=[1000, 2000]", "model.world_edges=radius"});
  EXPECT_FALSE(r.model.is_pb4u());
  EXPECT_EQ(r.model.latent, 32);
  EXPECT_FALSE(r.model.update_scaling_on());
  EXPECT_FALSE(r.model.graph_options().nearest_body_vertex_only);
  EXPECT_EQ(r.model.graph_options().material_ranges.mu, (std::vector<double>{1000, 2000}));
  const std::string path = test::temp_dir("model_config") + "/config.yaml";
  save_config(r, path);
  EXPECT_EQ(config_to_yaml(load_config<Root>(path)), config_to_yaml(r));
}

TEST(ModelConfig, BadValuesNameTheKey) {
  EXPECT_NE(error_of({"model.kind=gnn"}).find("model.kind"), std::string::npos);
  EXPECT_NE(error_of({"model.gamma=1.5"}).find("model.gamma"), std::string::npos);
  EXPECT_NE(error_of({"model.k_base=0"}).find("model.k_base"), std::string::npos);
  EXPECT_NE(error_of({"model.propagation_control=maybe"}).find("model.propagation_control"), std::string::npos);
  EXPECT_NE(error_of({"model.widht=3"}).find("widht"), std::string::npos);
  ModelConfig c;
  c.train_k_range = {3.0, 1.0};
  EXPECT_THROW(validate_model_config(c), Error);
}

}  // namespace
}  // namespace pb4u

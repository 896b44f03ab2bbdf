// The same weights under several inference passes (model/pass_variants.h), on the shipped files:
// pb4u.h5 carries the projection and the strain limit, mgn.h5 nothing.
#include <gtest/gtest.h>

#include "pb4u/model/pass_variants.h"
#include "pb4u/util/error.h"
#include "test_util.h"

namespace pb4u {
namespace {

std::vector<std::string> names_of(const std::vector<ModelFile>& models) {
  std::vector<std::string> out;
  for (const auto& m : models) out.push_back(method_name(m.config));
  return out;
}

TEST(PassVariants, EachNetworkAloneBesideItsOwnPassesDuplicatesDropped) {
  const std::vector<ModelFile> files{load_model_file(test::kSource + "/data/pretrained/pb4u.h5"),
                                     load_model_file(test::kSource + "/data/pretrained/mgn.h5")};
  ASSERT_EQ(method_name(files[0].config), "Pb4U + projection + strain limit");
  auto v = pass_variants(files, {"none", "shipped"});
  EXPECT_EQ(names_of(v), (std::vector<std::string>{"Pb4U", "Pb4U + projection + strain limit", "MGN"}));
  // The variants share their file's weights.
  EXPECT_EQ(v[0].model.get(), files[0].model.get());
  EXPECT_EQ(v[0].path, files[0].path);
  v = pass_variants(files, {"projection_strain"});
  EXPECT_EQ(names_of(v), (std::vector<std::string>{"Pb4U + projection + strain limit", "MGN + projection + strain limit"}));
  EXPECT_DOUBLE_EQ(v[1].config.contact_projection, kShippedProjectionGap);
  EXPECT_DOUBLE_EQ(v[1].config.strain_limit, kShippedStrainLimit);
  EXPECT_EQ(files[1].config.contact_projection, 0.0);  // the file itself unchanged
  // Refined: the two passes, then the reference solver with barrier contact, for any model.
  v = pass_variants(files, {"none", "refined"});
  const std::string refined_passes = " + projection + strain limit + 10 it + to 1 mm (barrier)";
  EXPECT_EQ(names_of(v), (std::vector<std::string>{"Pb4U", "Pb4U" + refined_passes, "MGN", "MGN" + refined_passes}));
  EXPECT_EQ(v[3].config.refine_iterations, kTableRefineIterations);
  EXPECT_DOUBLE_EQ(v[3].config.refine_tolerance_mm, kTableRefineToleranceMm);
  EXPECT_EQ(v[3].config.refine_contact, "barrier");
  EXPECT_DOUBLE_EQ(v[3].config.contact_projection, kShippedProjectionGap);
  EXPECT_EQ(v[2].config.refine_iterations, 0);
  // A file's own strain barrier in its refinement is not carried into `refined`.
  ModelFile barrier_refined = files[1];
  barrier_refined.config.refine_iterations = 3;
  barrier_refined.config.refine_strain_limit = 0.1;
  v = pass_variants({barrier_refined}, {"shipped", "refined"});
  ASSERT_EQ(v.size(), 2u);
  EXPECT_EQ(v[1].config.refine_strain_limit, 0.0);
  EXPECT_EQ(names_of(v)[1], "MGN" + refined_passes);
  // A refined file alone loses its refinement too.
  ModelFile refined = files[0];
  refined.config.refine_iterations = 5;
  v = pass_variants({refined}, {"shipped", "none", "projection_strain"});
  EXPECT_EQ(names_of(v), (std::vector<std::string>{"Pb4U + projection + strain limit + 5 it", "Pb4U",
                                                    "Pb4U + projection + strain limit"}));
  // And a file refined to a tolerance.
  refined.config.refine_iterations = 0;
  refined.config.refine_tolerance_mm = 1;
  v = pass_variants({refined}, {"shipped", "none"});
  EXPECT_EQ(names_of(v), (std::vector<std::string>{"Pb4U + projection + strain limit + to 1 mm", "Pb4U"}));
  EXPECT_EQ(v[1].config.refine_tolerance_mm, 0.0);
  // The refinement's part of a name, as evaluate's --refine / --refine-tolerance columns use it.
  EXPECT_EQ(refine_label(2, 1e-3), " + 2 it + to 0.001 mm");
  EXPECT_EQ(refine_label(0, 1), " + to 1 mm");
  EXPECT_EQ(refine_label(10, 0), " + 10 it");
}

TEST(PassVariants, UnknownOrNoEntryNamesTheKey) {
  const std::vector<ModelFile> files{load_model_file(test::kSource + "/data/pretrained/mgn.h5")};
  for (const std::vector<std::string>& bad : {std::vector<std::string>{"alone"}, std::vector<std::string>{}}) {
    try {
      pass_variants(files, bad, "bench.passes");
      FAIL();
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("bench.passes"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace pb4u

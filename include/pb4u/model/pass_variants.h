#pragma once
// The same weights under several inference passes, for tables that show each network alone
// beside its passes (`passes` in bench and evaluate configs). The passes are switches of a model
// file (model_config.h): the contact projection, the strain limit and the solver refinement.
#include <string>
#include <vector>

#include "pb4u/model/model_file.h"

namespace pb4u {

// The shipped Pb4U's two passes (data/pretrained/pb4u.h5): 2 mm out of the body, 10% strain.
inline constexpr double kShippedProjectionGap = 0.002;
inline constexpr double kShippedStrainLimit = 0.1;
// The refinement the tables report beside them (docs/physics.md): 10 iterations of the reference
// solver with barrier contact at most (fewer where its step is below 1 mm already), then on
// until the solver's step is below 1 mm.
inline constexpr int kTableRefineIterations = 10;
inline constexpr double kTableRefineToleranceMm = 1.0;

// Each model once per entry of `passes`, a model's variants together in the order given:
//   shipped            the file as it is;
//   none               the network alone (no projection, no strain limit, no refinement);
//   projection_strain  the shipped Pb4U's two passes and no refinement, for any model;
//   refined            those two passes, then the step refined by the reference solver with
//                      barrier contact (10 iterations, then on to 1 mm), for any model.
// A variant the same as an earlier one of the same file is dropped, so [none, shipped] on a file
// without passes gives one run. The variants share their file's weights. Throws pb4u::Error
// naming `key` on an unknown entry or an empty list.
std::vector<ModelFile> pass_variants(const std::vector<ModelFile>& models, const std::vector<std::string>& passes,
                                     const std::string& key = "passes");

}  // namespace pb4u

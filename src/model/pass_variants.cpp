#include "pb4u/model/pass_variants.h"

#include "pb4u/util/error.h"

namespace pb4u {

std::vector<ModelFile> pass_variants(const std::vector<ModelFile>& models, const std::vector<std::string>& passes,
                                     const std::string& key) {
  const std::string known = "(shipped | none | projection_strain | refined)";
  if (passes.empty()) throw Error(key + ": at least one entry " + known);
  for (const auto& p : passes)
    if (p != "shipped" && p != "none" && p != "projection_strain" && p != "refined")
      throw Error(key + ": unknown entry '" + p + "' " + known);
  std::vector<ModelFile> out;
  for (const ModelFile& m : models) {
    std::vector<ModelConfig> seen;
    for (const auto& p : passes) {
      ModelFile v = m;
      if (p != "shipped") {
        const bool refined = p == "refined";
        v.config.refine_iterations = refined ? kTableRefineIterations : 0;
        v.config.refine_tolerance_mm = refined ? kTableRefineToleranceMm : 0;
        v.config.refine_strain_limit = 0;  // the same refinement for every file, none of its own
        if (refined) v.config.refine_contact = "barrier";
        v.config.contact_projection = p == "none" ? 0.0 : kShippedProjectionGap;
        v.config.strain_limit = p == "none" ? 0.0 : kShippedStrainLimit;
      }
      const auto& c = v.config;
      bool duplicate = false;
      for (const auto& s : seen)
        duplicate = duplicate || (s.contact_projection == c.contact_projection && s.strain_limit == c.strain_limit &&
                                  s.refine_iterations == c.refine_iterations &&
                                  s.refine_tolerance_mm == c.refine_tolerance_mm && s.refine_contact == c.refine_contact &&
                                  s.refine_strain_limit == c.refine_strain_limit);
      if (duplicate) continue;
      seen.push_back(c);
      out.push_back(std::move(v));
    }
  }
  return out;
}

}  // namespace pb4u

#pragma once
// `pb4u generate`: bodies, motions and garments at every level, into one HDF5 dataset.
#include <string>
#include <vector>

#include "pb4u/body/mannequin.h"
#include "pb4u/body/procedural_motion.h"
#include "pb4u/config/config_io.h"
#include "pb4u/data/dataset.h"
#include "pb4u/data/levels.h"
#include "pb4u/garment/garment_template.h"

namespace pb4u {

// A mannequin built from a skeleton, or (with `mesh`) a skinned mesh file used as it is,
// whose animations join the motions as "<name>_<animation>". Garment templates are fitted
// around mannequins only (they need the mannequin's implicit surface); garment_files fit
// any body.
struct BodySpec {
  std::string name = "mannequin";
  std::string skeleton = "builtin";  // "builtin" or a BVH file whose rest skeleton is used
  std::string mesh;                  // skinned glTF/GLB/FBX/DAE; overrides `skeleton`

  template <class V>
  void visit(V& v) {
    v("name", name);
    v("skeleton", skeleton);
    v("mesh", mesh);
  }
};

struct ProceduralMotionSpec {
  std::string body = "mannequin";
  std::vector<std::string> kinds = {"walk", "run", "jump", "arm_raise", "torso_twist", "spin"};
  int per_kind = 2;
  int frames = 90;
  MotionRanges ranges;
  // Held-out motions (split "heldout"): heldout_per_kind of each kind with parameters drawn
  // from heldout_ranges (set them outside `ranges`), heldout_frames long.
  int heldout_per_kind = 0;
  int heldout_frames = 300;
  MotionRanges heldout_ranges{{1.5, 1.8}, {1.35, 1.5}};

  template <class V>
  void visit(V& v) {
    v("body", body);
    v("kinds", kinds);
    v("per_kind", per_kind, int_at_least(0));
    v("frames", frames, int_at_least(2));
    v("ranges", ranges);
    v("heldout_per_kind", heldout_per_kind, int_at_least(0));
    v("heldout_frames", heldout_frames, int_at_least(2));
    v("heldout_ranges", heldout_ranges);
  }
};

struct BvhMotionSpec {
  std::string body = "cmu131";
  std::vector<std::string> files;
  std::vector<std::string> heldout_files;  // split "heldout": never trained on
  int max_frames = 0;  // 0 = whole file
  double scale = 1.0;  // file units to metres

  template <class V>
  void visit(V& v) {
    v("body", body);
    v("files", files);
    v("heldout_files", heldout_files);
    v("max_frames", max_frames, int_at_least(0));
    v("scale", scale, positive());
  }
};

struct GenerateConfig {
  std::string file = "dataset.h5";  // written inside --out
  int seed = 1;
  double fps = 30.0;
  double density = 0.20022;  // kg/m^2 for the stored masses (SPEC 2)
  double test_fraction = 0.25;
  LevelsConfig levels;
  std::vector<BodySpec> bodies = {BodySpec{}};
  MannequinConfig mannequin;
  std::vector<std::string> templates = {"tshirt", "tank_top", "long_sleeve", "long_dress", "skirt"};
  std::vector<std::string> garment_files;  // user garments, fitted around every body
  GarmentTemplateConfig garments;
  ProceduralMotionSpec procedural;
  BvhMotionSpec bvh;

  template <class V>
  void visit(V& v) {
    v("file", file);
    v("seed", seed);
    v("fps", fps, positive());
    v("density", density, positive());
    v("test_fraction", test_fraction, in_range(0.0, 1.0));
    v("levels", levels);
    v("bodies", bodies);
    v("mannequin", mannequin);
    v("templates", templates);
    v("garment_files", garment_files);
    v("garments", garments);
    v("procedural", procedural);
    v("bvh", bvh);
  }
};

// Checks cross-field consistency (names, levels, body references); `where` names the config.
void validate_generate_config(const GenerateConfig& config, const std::string& where);

// Builds everything the config asks for. Relative paths are tried against the working
// directory, then against `base_dir` (the config file's directory). Garments are built on
// `workers` threads (0 = one per core); the result does not depend on the count.
Dataset generate_dataset(const GenerateConfig& config, const std::string& base_dir = "",
                         int workers = 0);

}  // namespace pb4u

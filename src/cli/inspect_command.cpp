// `pb4u inspect FILE`: a quick, read-only summary of anything pb4u reads.
#include <CLI/CLI.hpp>
#include <iostream>

#include "pb4u/body/bvh.h"
#include "pb4u/cli/commands.h"
#include "pb4u/data/dataset.h"
#include "pb4u/model/model_file.h"
#include "pb4u/io/mesh_io.h"
#include "pb4u/io/mesh_summary.h"

namespace pb4u {
namespace {

void print_bvh_summary(std::ostream& out, const std::string& path) {
  const BvhFile bvh = read_bvh(path, 0.0);
  const Motion at30 = resample_motion(bvh.motion, 30.0);
  out << "kind: motion (BVH)\n";
  out << "joints: " << bvh.skeleton.num_joints() << "\n";
  out << "frames: " << bvh.source_frames << " at " << bvh.source_fps << " fps ("
      << at30.num_frames() << " at 30 fps)\n";
  out << "duration: " << bvh.motion.duration() << " s\n";
  out << "root:";
  for (int j = 0; j < bvh.skeleton.num_joints(); ++j) {
    if (j == 1) out << "\njoint names:";
    out << " " << bvh.skeleton.names[j];
  }
  out << "\n";
}

}  // namespace

void add_inspect_command(CLI::App& app, const GlobalOptions& global) {
  auto* cmd = app.add_subcommand(
      "inspect",
      "Summarise a file: for a mesh (OBJ, PLY, STL, glTF/GLB, FBX, DAE) its counts, components,\n"
      "boundary loops, manifoldness, degenerate faces, mean edge length and bounding box; for a\n"
      "BVH motion its joints, frames and frame rate; for a dataset (.h5) its levels, bodies,\n"
      "garments and motions; for a model (training checkpoint .pt or `pb4u export` .h5) its\n"
      "method, parameter count, calibration and config.");
  auto path = std::make_shared<std::string>();
  cmd->add_option("file", *path, "File to summarise")->required();
  cmd->callback([path, &global] {
    apply_global_options(global);
    const std::string ext = file_extension(*path);
    if (ext == ".bvh") {
      std::ostringstream text;  // nothing printed if reading throws
      print_bvh_summary(text, *path);
      std::cout << "file: " << *path << "\n" << text.str();
    } else if (ext == ".pt" || ((ext == ".h5" || ext == ".hdf5") && is_model_export(*path))) {
      const ModelFile model = load_model_file(*path);
      std::cout << "file: " << *path << "\n";
      print_model_summary(std::cout, model);
    } else if (ext == ".h5" || ext == ".hdf5") {
      const Dataset data = read_dataset(*path);
      std::cout << "file: " << *path << "\n";
      print_dataset_summary(std::cout, data);
    } else {
      MeshSummary summary = summarize_mesh_file(*path);  // nothing printed if this throws
      std::cout << "file: " << *path << "\n";
      print_mesh_summary(std::cout, summary);
    }
  });
}

}  // namespace pb4u

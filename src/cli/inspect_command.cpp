// `pb4u inspect FILE`: a quick, read-only summary of anything pb4u reads.
#include <CLI/CLI.hpp>
#include <iostream>

#include "pb4u/cli/commands.h"
#include "pb4u/io/mesh_io.h"
#include "pb4u/io/mesh_summary.h"

namespace pb4u {

void add_inspect_command(CLI::App& app, const GlobalOptions& global) {
  auto* cmd = app.add_subcommand(
      "inspect",
      "Summarise a file: for a mesh (OBJ, PLY, STL, glTF/GLB, FBX, DAE) its counts, components,\n"
      "boundary loops, manifoldness, degenerate faces, mean edge length and bounding box.");
  auto path = std::make_shared<std::string>();
  cmd->add_option("file", *path, "File to summarise")->required();
  cmd->callback([path, &global] {
    apply_global_options(global);
    MeshSummary summary = summarize_mesh_file(*path);  // nothing printed if this throws
    std::cout << "file: " << *path << "\n";
    print_mesh_summary(std::cout, summary);
  });
}

}  // namespace pb4u

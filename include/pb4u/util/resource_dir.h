#pragma once
// Where pb4u finds what it ships beside the binary: scripts/ (plots, preview, Blender's cloth),
// configs/ and data/ (meshes, motions, the pretrained models). In order:
//   1. $PB4U_DATA_DIR, when set (it must hold scripts/);
//   2. an installed tree: <prefix>/share/pb4u for the binary <prefix>/bin/pb4u;
//   3. a source checkout holding the binary's build directory (<checkout>/build/pb4u).
// Nothing is taken from where the sources were when pb4u was compiled: an installed pb4u
// runs with its checkout moved or deleted.
#include <string>

namespace pb4u {

// The directory holding scripts/, configs/ and data/, or "" when none is found.
std::string resource_dir();

// <resource_dir>/<relative> when that exists; "" otherwise.
std::string resource_path(const std::string& relative);

// The directory of the running executable (/proc/self/exe).
std::string executable_dir();

}  // namespace pb4u

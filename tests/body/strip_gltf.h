#pragma once
// A two-bone skinned, animated glTF strip (defined in skinned_mesh_test.cpp).
#include <string>

namespace pb4u::test {

// glTF 2.0 JSON with an embedded buffer: joints Root and Bone, animation "bend" (1 s).
std::string strip_gltf();

}  // namespace pb4u::test

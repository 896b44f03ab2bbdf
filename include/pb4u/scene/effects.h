#pragma once
// The effects a scene calls for (SPEC 6). Stretch, bending and inertia are the cloth itself
// and always on; these four are optional, and only what is on is built and computed.
#include <string>
#include <vector>

namespace pb4u {

struct Effects {
  bool gravity = true;
  bool collision = true;  // needs a body
  bool friction = true;   // needs a body
  bool pins = false;
  // Cloth against itself: ContourCraft's repulsion term (physics/repulsion_energy.h). Not a
  // network input: the networks' four effect flags are the four above.
  bool self_collision = false;

  bool needs_body() const { return collision || friction; }

  // From a scene's list, e.g. ["gravity", "collision"]. Throws pb4u::Error naming `where`
  // on an unknown name.
  static Effects from_names(const std::vector<std::string>& names, const std::string& where);
  std::vector<std::string> names() const;
};

}  // namespace pb4u

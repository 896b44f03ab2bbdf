#include "pb4u/scene/effects.h"

#include "pb4u/util/error.h"

namespace pb4u {

Effects Effects::from_names(const std::vector<std::string>& names, const std::string& where) {
  Effects e;
  e.gravity = e.collision = e.friction = e.pins = e.self_collision = false;
  for (const auto& n : names) {
    if (n == "gravity") e.gravity = true;
    else if (n == "collision") e.collision = true;
    else if (n == "friction") e.friction = true;
    else if (n == "pins") e.pins = true;
    else if (n == "self_collision") e.self_collision = true;
    else throw Error(where + ": unknown effect '" + n + "' (known: gravity, collision, friction, pins, self_collision)");
  }
  return e;
}

std::vector<std::string> Effects::names() const {
  std::vector<std::string> out;
  if (gravity) out.push_back("gravity");
  if (collision) out.push_back("collision");
  if (friction) out.push_back("friction");
  if (pins) out.push_back("pins");
  if (self_collision) out.push_back("self_collision");
  return out;
}

}  // namespace pb4u

#include "pb4u/scene/waistband.h"

#include <algorithm>

namespace pb4u {

bool WaistbandConfig::holds(const std::string& garment) const {
  return band > 0 && std::find(garments.begin(), garments.end(), garment) != garments.end();
}

}  // namespace pb4u

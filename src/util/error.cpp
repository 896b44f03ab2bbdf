#include "pb4u/util/error.h"

namespace pb4u {

void fail_file(const std::string& path, const std::string& message) {
  throw Error(path + ": " + message);
}

}  // namespace pb4u

#include "pb4u/cli/commands.h"
#include "pb4u/util/runtime.h"

int main(int argc, char** argv) {
  pb4u::ensure_fast_runtime(argc, argv);  // may re-execute with OPENBLAS_CORETYPE, OMP_WAIT_POLICY set
  pb4u::tune_allocator();
  return pb4u::run_cli(argc, argv);
}

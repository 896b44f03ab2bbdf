#pragma once
// Process-level set-up that must happen before any heavy work: an optimised
// BLAS kernel, thread counts, allocator tuning, logging.
#include <string>

namespace pb4u {

// Settings that libraries read only when they load, so they must be in the environment before
// the program starts: if any needs to change, this sets it and re-executes the program once.
// - OpenBLAS picks its kernels at load. On some VMs it detects the CPU as a generic core
//   ("Prescott") and runs 3-4x slower than it could; if the CPU supports AVX-512 / AVX2 this
//   sets OPENBLAS_CORETYPE.
// - libgomp's idle threads spin; under load that starves the work (OMP_WAIT_POLICY=PASSIVE).
// A variable the user set is kept. Returns normally when nothing needs to change. Set
// PB4U_NO_REEXEC=1 to disable.
void ensure_fast_runtime(int argc, char** argv);

// The BLAS core in use, e.g. "SkylakeX", or "reference" when libblas.so.3 is not OpenBLAS.
std::string blas_core_name();

// Keeps freed large blocks in the heap instead of returning them to the OS (glibc mallopt), so
// per-frame activations do not page-fault afresh. PB4U_DEFAULT_MALLOC=1 keeps glibc's defaults.
void tune_allocator();

// Sets torch's intra-op threads (0 = all cores) and returns the count in use.
int configure_threads(int requested);

// One log line: BLAS core, thread count, torch version.
void log_runtime_info();

}  // namespace pb4u

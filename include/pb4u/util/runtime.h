#pragma once
// Process-level set-up that must happen before any heavy work: an optimised
// BLAS kernel, thread counts, allocator tuning, logging.
#include <string>

namespace pb4u {

// OpenBLAS picks its kernels when it is loaded. On some VMs it detects the CPU
// as a generic core ("Prescott") and runs 4x slower than it could. If so, and
// the CPU supports AVX-512 / AVX2, this sets OPENBLAS_CORETYPE and re-executes
// the program (once) so the loader picks the fast kernels. Returns normally
// when nothing needs to change. Set PB4U_NO_BLAS_REEXEC=1 to disable.
void ensure_fast_blas(int argc, char** argv);

// The BLAS core in use, e.g. "SkylakeX", or "reference" when libblas.so.3 is not OpenBLAS.
std::string blas_core_name();

// Sets torch's intra-op threads (0 = all cores) and returns the count in use.
int configure_threads(int requested);

// One log line: BLAS core, thread count, torch version.
void log_runtime_info();

}  // namespace pb4u

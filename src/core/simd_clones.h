// Run-time dispatch of the point kernels (binning, voxel accumulation) to the CPU's vector width.
#pragma once

// One portable binary, with AVX-512 and AVX2/FMA clones picked at run time where the CPU has them.
// Not under ThreadSanitizer: the clones' ifunc resolver, instrumented, runs while the dynamic loader
// relocates the library, before the TSan runtime is set up, and every executable linking the core
// crashed at start (scripts/dev/test --sanitize).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_THREAD__)
#define SCL_CLONES __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define SCL_CLONES
#endif

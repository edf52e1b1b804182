#pragma once
// Which instruction set the batch kernels (8 configurations per call) run with: AVX2 + FMA when
// the CPU has them, else the portable x86-64 build. Chosen once at run time; tests force the
// portable path to check it on any machine.
namespace dmgplace::runtime {

enum class SimdPath { Portable, Avx2 };

SimdPath simd_path();                      // the path in use
void force_simd_path(SimdPath p);          // tests; Avx2 is refused (stays Portable) without the CPU
const char* to_string(SimdPath p);

}  // namespace dmgplace::runtime

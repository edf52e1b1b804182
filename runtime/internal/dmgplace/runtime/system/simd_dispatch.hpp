#pragma once
// Which instruction set the lane kernels (8 configurations per call) run with: AVX2 + FMA when
// the CPU has them, else the portable x86-64 build. Chosen once at run time; tests force the
// portable path to check it on any machine.
namespace dmgplace::runtime {

enum class SimdPath { Portable, Avx2 };

SimdPath simd_path();              // the path in use
void force_simd_path(SimdPath p);  // tests; Avx2 is refused (stays Portable) without the CPU
const char* to_string(SimdPath p);

// Puts back the path in use when it was made: a test that forces a path cannot leak it into the
// next one, even when a failed ASSERT returns early.
class ScopedSimdPath {
 public:
  ScopedSimdPath() : saved_(simd_path()) {}
  explicit ScopedSimdPath(SimdPath p) : saved_(simd_path()) { force_simd_path(p); }
  ~ScopedSimdPath() { force_simd_path(saved_); }
  ScopedSimdPath(const ScopedSimdPath&) = delete;
  ScopedSimdPath& operator=(const ScopedSimdPath&) = delete;

 private:
  SimdPath saved_;
};

}  // namespace dmgplace::runtime

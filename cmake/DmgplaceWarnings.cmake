# Warnings for our own targets only; dependencies come in as SYSTEM includes.
function(dmgplace_target_defaults target)
  # -Wno-restrict: GCC 12 false positive inside std::string (GCC bug 105329).
  # -Wno-psabi: GCC's notes on how vector arguments were passed before GCC 4.6; the SIMD lanes
  # (runtime/system/lanes.hpp) never cross a call, and a pragma cannot silence these notes.
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wno-unused-parameter
                                           $<$<CXX_COMPILER_ID:GNU>:-Wno-restrict -Wno-psabi>)
  if(DMGPLACE_SANITIZE)
    target_compile_options(${target} PRIVATE -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
    target_link_options(${target} PRIVATE -fsanitize=address,undefined)
    # Under ASan, Eigen switches to its own aligned malloc (it checks __SANITIZE_ADDRESS__), while
    # the uninstrumented libraries (PCL) keep glibc's: point clouds allocated there and freed here
    # then look like heap overflows. glibc's malloc is 16-byte aligned on x86_64, which is all Eigen needs.
    target_compile_definitions(${target} PRIVATE EIGEN_MALLOC_ALREADY_ALIGNED=1)
  endif()
  if(DMGPLACE_FUZZ)
    # Coverage instrumentation for libFuzzer plus ASan+UBSan (UB aborts, so the fuzzer sees it);
    # the fuzz targets themselves add -fsanitize=fuzzer (tests/fuzz). Eigen: as for DMGPLACE_SANITIZE.
    target_compile_options(${target} PRIVATE -fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer
                                             -fno-sanitize-recover=undefined)
    target_link_options(${target} PRIVATE -fsanitize=address,undefined)
    target_compile_definitions(${target} PRIVATE EIGEN_MALLOC_ALREADY_ALIGNED=1)
  endif()
  if(DMGPLACE_TSAN)
    target_compile_options(${target} PRIVATE -fsanitize=thread -fno-omit-frame-pointer)
    target_link_options(${target} PRIVATE -fsanitize=thread)
  endif()
endfunction()

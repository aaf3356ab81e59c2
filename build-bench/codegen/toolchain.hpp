// Where `mbrt sim` finds the compiler, the runtime headers and its driver.
// Filled in by CMake at configure time.
#pragma once

namespace mbrt::codegen::toolchain {
inline constexpr const char* kCompiler = "/usr/bin/c++";
inline constexpr const char* kRuntimeInclude = "/work/main/include";
inline constexpr const char* kEigenInclude = "/usr/include/eigen3";
inline constexpr const char* kDriverSource = "/work/main/codegen/sim_driver.cpp";
inline constexpr const char* kFlags = "-std=c++20 -O3 -DNDEBUG";
// Added where the CPU has AVX2 and FMA (not -march=native: valgrind, which
// timing/ uses to count instructions, does not decode AVX-512).
inline constexpr const char* kVectorFlags = "-march=x86-64-v3";
}  // namespace mbrt::codegen::toolchain

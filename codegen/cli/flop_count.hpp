// Floating-point operations and instructions of one step(), counted in the
// compiled program that `mbrt sim` runs. valgrind's callgrind executes it for
// N and 2N steps with a count per machine instruction (start-up and output
// cancel in the difference); objdump names each instruction, and every
// executed arithmetic instruction on doubles adds its lanes: scalar 1, 128-bit
// 2, 256-bit 4, and twice that for a fused multiply-add. Compares, min/max,
// conversions, moves, shuffles and sign masks are not floating-point
// operations here.
#pragma once

#include <string>

namespace mbrt::codegen {

struct StepCount {
  double flops = 0.0;
  double instructions = 0.0;
};

// Floating-point operations of one x86-64 instruction in AT&T syntax
// (objdump's), e.g. ("vfmadd231pd", "%ymm2,%ymm1,%ymm0") -> 8.
int flops_of_instruction(const std::string& mnemonic, const std::string& operands);

// Runs `executable ARGS --t-end T` under callgrind for steps and 2 steps
// steps of length h and returns the per-step difference. Throws
// std::runtime_error when valgrind or objdump is missing or fails.
StepCount count_step(const std::string& executable, double h, int steps);

}  // namespace mbrt::codegen

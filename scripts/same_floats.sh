# shellcheck shell=bash
# Source this file (bash) for the same floating-point results on every x86-64 machine with AVX2.
# numpy picks its SIMD kernels by processor (AVX-512 where there is one), and their last bits
# steer the simulator's contacts: measured 2026-11-26, `run_experiment --damage-kind
# unpowered_coxa` gave a blind ratio median of 0.943 on an AVX-512 machine, and 0.940, the figure
# of 2026-11-25's machine to the last digit, on the same machine with numpy's AVX-512 kernels off.
# A choice you made stays.
if [ "$(uname -m)" = x86_64 ]; then
  export NPY_DISABLE_CPU_FEATURES="${NPY_DISABLE_CPU_FEATURES-X86_V4 AVX512_ICL AVX512_SPR}"
fi

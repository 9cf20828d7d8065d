// Per-sample code compiled for the host CPU's widest vector instructions (issue 9). The project is
// built for baseline x86-64 (SSE2) so that one binary runs on every x86-64 machine; a function
// marked RL_WIDEST is compiled twice by GCC -- for x86-64-v3 (AVX2: VEX three-operand
// instructions, 8-wide vectors) and for the baseline -- and the copy the CPU runs is picked at load
// time (target_clones: an ifunc). `flatten` inlines everything it calls (within its translation
// unit) into each copy, so the whole call tree below it gets the wider instruction set. (ReSTIR
// DI's SIMD batch of light candidates, di_sampling.cpp, was the first such function.)
// -ffp-contract=off (CMakeLists.txt) forbids fused multiply-adds, and neither copy reorders
// floating-point arithmetic (no fast-math), so both compute the same floats: the image does not
// depend on the machine. Mark only entry points of scalar-heavy per-sample work whose gain was
// measured (the path tracer's shading, ReSTIR PT's paths and shifts: 18-25% less stage time); where
// the time is in Embree or in cache misses (ReSTIR DI's reuse, the G-buffer) no gain was resolved.
// Each call costs one indirect jump: mark functions doing at least a pixel's work.
#pragma once

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__CUDACC__)
#define RL_WIDEST [[gnu::flatten, gnu::target_clones("arch=x86-64-v3", "default")]]
#else
#define RL_WIDEST
#endif

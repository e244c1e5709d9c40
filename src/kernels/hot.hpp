// SPDX-License-Identifier: MIT
#pragma once
/// @file SB_HOT_KERNEL marks the few kernels that run in every Newton iteration of every span or
/// triad. GCC compiles them twice, for x86-64-v3 (AVX2, FMA) and for the baseline, and the
/// loader picks the clone the CPU can run (function multiversioning): the build stays portable
/// while machines that have FMA use it (pendulum64: 4 % of a time step).
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define SB_HOT_KERNEL __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define SB_HOT_KERNEL
#endif

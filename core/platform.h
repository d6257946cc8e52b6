// Host/device platform macros shared by every header that the CPU tracers and the CUDA kernels both compile.
// Code under RAYCOH_HD is plain structs and free functions: no std containers, exceptions or virtual calls.
#pragma once

#if defined(__CUDACC__)
#define RAYCOH_HD __host__ __device__
#define RAYCOH_INLINE __forceinline__
#else
#define RAYCOH_HD
#define RAYCOH_INLINE inline __attribute__((always_inline))
#endif

#include <cstdint>

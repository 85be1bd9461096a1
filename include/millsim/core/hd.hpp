#pragma once
// MILLSIM_HD marks functions that run on the host and on a CUDA device. Every physics functor
// (force law, integrator update) carries it so the OpenMP loop and the CUDA kernel call the
// same code: one source of physics.
#if defined(__CUDACC__)
#define MILLSIM_HD __host__ __device__
#define MILLSIM_DEVICE __device__
#else
#define MILLSIM_HD
#define MILLSIM_DEVICE
#endif

#if defined(__CUDACC__) || defined(__CUDA_ARCH__)
#define MILLSIM_INLINE __forceinline__
#else
#define MILLSIM_INLINE inline
#endif

// Inlining that the compiler must not decline: the SPH pair terms are called from deep inside
// the search lambdas, where GCC's heuristics left them as calls (the 2D pair loop spent more
// time calling than computing).
#if defined(__CUDACC__) || defined(__CUDA_ARCH__)
#define MILLSIM_FORCE_INLINE __forceinline__
#elif defined(__GNUC__)
#define MILLSIM_FORCE_INLINE inline __attribute__((always_inline))
#else
#define MILLSIM_FORCE_INLINE inline
#endif

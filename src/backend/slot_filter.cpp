#include "millsim/neighbors/slot_filter.hpp"

#include <cstdint>

#include "millsim/backend/simd.hpp"

#if defined(MILLSIM_HAVE_SIMD_LEVELS)
#include <immintrin.h>
#endif

namespace millsim::neighbors {
namespace {

// One candidate at a time, without a branch: every slot is written, the count moves on hits.
template <class T>
int filterScalar(const int* begin, const int* end, int ranges, core::Vec3<T> p, T radius2, const core::Vec3<T>* pos,
                 int* hit, T* hit_r2) {
  int n = 0;
  for (int k = 0; k < ranges; ++k)
    for (int s = begin[k]; s < end[k]; ++s) {
      const T r2 = core::norm2(p - pos[s]);
      hit[n] = s;
      hit_r2[n] = r2;
      n += r2 < radius2 ? 1 : 0;
    }
  return n;
}

#if defined(MILLSIM_HAVE_SIMD_LEVELS)
static_assert(sizeof(core::Vec3<float>) == 3 * sizeof(float) && sizeof(core::Vec3<double>) == 3 * sizeof(double),
              "the vector filters read positions as packed x, y, z");

// The bits of the first `count` positions' 3 count components, for the load masks of a partial
// vector at the end of a range (count < 16: at most 45 bits).
inline std::uint64_t componentMask(int count) { return (std::uint64_t{1} << (3 * count)) - 1; }

// 16 positions per vector. Loads of 48 floats are de-interleaved by two two-source permutes per
// coordinate: the first picks what lies in the first 32 floats, the second adds the rest from
// the third load. Hits are compressed in registers and stored whole (a compressing store to
// memory is microcoded and slow on AMD's Zen 4).
MILLSIM_TARGET_AVX512 int filterAvx512(const int* begin, const int* end, int ranges, core::Vec3<float> p, float radius2,
                                       const core::Vec3<float>* pos, int* hit, float* hit_r2) {
  const __m512i x_ab = _mm512_setr_epi32(0, 3, 6, 9, 12, 15, 18, 21, 24, 27, 30, 0, 0, 0, 0, 0);
  const __m512i x_c = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 17, 20, 23, 26, 29);
  const __m512i y_ab = _mm512_setr_epi32(1, 4, 7, 10, 13, 16, 19, 22, 25, 28, 31, 0, 0, 0, 0, 0);
  const __m512i y_c = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 18, 21, 24, 27, 30);
  const __m512i z_ab = _mm512_setr_epi32(2, 5, 8, 11, 14, 17, 20, 23, 26, 29, 0, 0, 0, 0, 0, 0);
  const __m512i z_c = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 16, 19, 22, 25, 28, 31);
  const __m512i lane = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const __m512 px = _mm512_set1_ps(p.x), py = _mm512_set1_ps(p.y), pz = _mm512_set1_ps(p.z);
  const __m512 reach2 = _mm512_set1_ps(radius2);
  int n = 0;
  for (int k = 0; k < ranges; ++k)
    for (int s = begin[k], e = end[k]; s < e; s += 16) {
      const int count = e - s < 16 ? e - s : 16;
      const float* f = &pos[s].x;
      __m512 a, b, c;
      if (count == 16) {
        a = _mm512_loadu_ps(f), b = _mm512_loadu_ps(f + 16), c = _mm512_loadu_ps(f + 32);
      } else {
        const std::uint64_t m = componentMask(count);
        a = _mm512_maskz_loadu_ps(static_cast<__mmask16>(m), f);
        b = _mm512_maskz_loadu_ps(static_cast<__mmask16>(m >> 16), f + 16);
        c = _mm512_maskz_loadu_ps(static_cast<__mmask16>(m >> 32), f + 32);
      }
      const __m512 dx = _mm512_sub_ps(px, _mm512_permutex2var_ps(_mm512_permutex2var_ps(a, x_ab, b), x_c, c));
      const __m512 dy = _mm512_sub_ps(py, _mm512_permutex2var_ps(_mm512_permutex2var_ps(a, y_ab, b), y_c, c));
      const __m512 dz = _mm512_sub_ps(pz, _mm512_permutex2var_ps(_mm512_permutex2var_ps(a, z_ab, b), z_c, c));
      const __m512 r2 =
          _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(dx, dx), _mm512_mul_ps(dy, dy)), _mm512_mul_ps(dz, dz));
      const __mmask16 valid = static_cast<__mmask16>((1u << count) - 1);
      const __mmask16 in = _mm512_mask_cmp_ps_mask(valid, r2, reach2, _CMP_LT_OQ);
      const __m512i slot = _mm512_add_epi32(_mm512_set1_epi32(s), lane);
      _mm512_storeu_si512(hit + n, _mm512_maskz_compress_epi32(in, slot));
      _mm512_storeu_ps(hit_r2 + n, _mm512_maskz_compress_ps(in, r2));
      n += __builtin_popcount(in);
    }
  return n;
}

// 8 positions per vector, as above with 24 doubles.
MILLSIM_TARGET_AVX512 int filterAvx512(const int* begin, const int* end, int ranges, core::Vec3<double> p,
                                       double radius2, const core::Vec3<double>* pos, int* hit, double* hit_r2) {
  const __m512i x_ab = _mm512_setr_epi64(0, 3, 6, 9, 12, 15, 0, 0);
  const __m512i x_c = _mm512_setr_epi64(0, 1, 2, 3, 4, 5, 10, 13);
  const __m512i y_ab = _mm512_setr_epi64(1, 4, 7, 10, 13, 0, 0, 0);
  const __m512i y_c = _mm512_setr_epi64(0, 1, 2, 3, 4, 8, 11, 14);
  const __m512i z_ab = _mm512_setr_epi64(2, 5, 8, 11, 14, 0, 0, 0);
  const __m512i z_c = _mm512_setr_epi64(0, 1, 2, 3, 4, 9, 12, 15);
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m512d px = _mm512_set1_pd(p.x), py = _mm512_set1_pd(p.y), pz = _mm512_set1_pd(p.z);
  const __m512d reach2 = _mm512_set1_pd(radius2);
  int n = 0;
  for (int k = 0; k < ranges; ++k)
    for (int s = begin[k], e = end[k]; s < e; s += 8) {
      const int count = e - s < 8 ? e - s : 8;
      const double* f = &pos[s].x;
      __m512d a, b, c;
      if (count == 8) {
        a = _mm512_loadu_pd(f), b = _mm512_loadu_pd(f + 8), c = _mm512_loadu_pd(f + 16);
      } else {
        const std::uint64_t m = componentMask(count);
        a = _mm512_maskz_loadu_pd(static_cast<__mmask8>(m), f);
        b = _mm512_maskz_loadu_pd(static_cast<__mmask8>(m >> 8), f + 8);
        c = _mm512_maskz_loadu_pd(static_cast<__mmask8>(m >> 16), f + 16);
      }
      const __m512d dx = _mm512_sub_pd(px, _mm512_permutex2var_pd(_mm512_permutex2var_pd(a, x_ab, b), x_c, c));
      const __m512d dy = _mm512_sub_pd(py, _mm512_permutex2var_pd(_mm512_permutex2var_pd(a, y_ab, b), y_c, c));
      const __m512d dz = _mm512_sub_pd(pz, _mm512_permutex2var_pd(_mm512_permutex2var_pd(a, z_ab, b), z_c, c));
      const __m512d r2 =
          _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy)), _mm512_mul_pd(dz, dz));
      const __mmask8 valid = static_cast<__mmask8>((1u << count) - 1);
      const __mmask8 in = _mm512_mask_cmp_pd_mask(valid, r2, reach2, _CMP_LT_OQ);
      const __m256i slot = _mm256_add_epi32(_mm256_set1_epi32(s), lane);
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(hit + n), _mm256_maskz_compress_epi32(in, slot));
      _mm512_storeu_pd(hit_r2 + n, _mm512_maskz_compress_pd(in, r2));
      n += __builtin_popcount(in);
    }
  return n;
}
#endif

}  // namespace

template <class T>
int filterRangesInOrder(const int* begin, const int* end, int ranges, core::Vec3<T> p, T radius2,
                        const core::Vec3<T>* pos, int* hit, T* hit_r2) {
#if defined(MILLSIM_HAVE_SIMD_LEVELS)
  if (backend::simdLevel() == backend::SimdLevel::kAvx512)
    return filterAvx512(begin, end, ranges, p, radius2, pos, hit, hit_r2);
#endif
  return filterScalar(begin, end, ranges, p, radius2, pos, hit, hit_r2);
}

template int filterRangesInOrder<float>(const int*, const int*, int, core::Vec3<float>, float, const core::Vec3<float>*,
                                        int*, float*);
template int filterRangesInOrder<double>(const int*, const int*, int, core::Vec3<double>, double,
                                         const core::Vec3<double>*, int*, double*);

}  // namespace millsim::neighbors

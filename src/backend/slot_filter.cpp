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

// AVX2 has no compress: the hit mask picks a row of a table of lane numbers (the set lanes
// first, in order), and a permute moves the hits to the front. kPick8[m]: lanes of the set
// bits of an 8-bit mask; kPickPairs4[m]: the 32-bit halves (2 lane, 2 lane + 1) of the set bits
// of a 4-bit mask, to move doubles with the same permute.
struct PickTables {
  alignas(32) int pick8[256][8];
  alignas(32) int pick_pairs4[16][8];
  constexpr PickTables() : pick8{}, pick_pairs4{} {
    for (int m = 0; m < 256; ++m) {
      int k = 0;
      for (int lane = 0; lane < 8; ++lane)
        if (m & (1 << lane)) pick8[m][k++] = lane;
    }
    for (int m = 0; m < 16; ++m) {
      int k = 0;
      for (int lane = 0; lane < 4; ++lane)
        if (m & (1 << lane)) pick_pairs4[m][k++] = 2 * lane, pick_pairs4[m][k++] = 2 * lane + 1;
    }
  }
};
constexpr PickTables kPick{};

// 8 positions per vector: 24 floats in three loads; each coordinate is three single-source
// permutes and two blends.
MILLSIM_TARGET_AVX2 int filterAvx2(const int* begin, const int* end, int ranges, core::Vec3<float> p, float radius2,
                                   const core::Vec3<float>* pos, int* hit, float* hit_r2) {
  const __m256i x_a = _mm256_setr_epi32(0, 3, 6, 0, 0, 0, 0, 0), x_b = _mm256_setr_epi32(0, 0, 0, 1, 4, 7, 0, 0),
                x_c = _mm256_setr_epi32(0, 0, 0, 0, 0, 0, 2, 5);
  const __m256i y_a = _mm256_setr_epi32(1, 4, 7, 0, 0, 0, 0, 0), y_b = _mm256_setr_epi32(0, 0, 0, 2, 5, 0, 0, 0),
                y_c = _mm256_setr_epi32(0, 0, 0, 0, 0, 0, 3, 6);
  const __m256i z_a = _mm256_setr_epi32(2, 5, 0, 0, 0, 0, 0, 0), z_b = _mm256_setr_epi32(0, 0, 0, 3, 6, 0, 0, 0),
                z_c = _mm256_setr_epi32(0, 0, 0, 0, 0, 1, 4, 7);
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256 px = _mm256_set1_ps(p.x), py = _mm256_set1_ps(p.y), pz = _mm256_set1_ps(p.z);
  const __m256 reach2 = _mm256_set1_ps(radius2);
  int n = 0;
  for (int k = 0; k < ranges; ++k)
    for (int s = begin[k], e = end[k]; s < e; s += 8) {
      const int count = e - s < 8 ? e - s : 8;
      const float* f = &pos[s].x;
      __m256 a, b, c;
      if (count == 8) {
        a = _mm256_loadu_ps(f), b = _mm256_loadu_ps(f + 8), c = _mm256_loadu_ps(f + 16);
      } else {
        const __m256i comps = _mm256_set1_epi32(3 * count);
        a = _mm256_maskload_ps(f, _mm256_cmpgt_epi32(comps, lane));
        b = _mm256_maskload_ps(f + 8, _mm256_cmpgt_epi32(comps, _mm256_add_epi32(lane, _mm256_set1_epi32(8))));
        c = _mm256_maskload_ps(f + 16, _mm256_cmpgt_epi32(comps, _mm256_add_epi32(lane, _mm256_set1_epi32(16))));
      }
      const __m256 xa = _mm256_permutevar8x32_ps(a, x_a), xb = _mm256_permutevar8x32_ps(b, x_b),
                   xc = _mm256_permutevar8x32_ps(c, x_c);
      const __m256 ya = _mm256_permutevar8x32_ps(a, y_a), yb = _mm256_permutevar8x32_ps(b, y_b),
                   yc = _mm256_permutevar8x32_ps(c, y_c);
      const __m256 za = _mm256_permutevar8x32_ps(a, z_a), zb = _mm256_permutevar8x32_ps(b, z_b),
                   zc = _mm256_permutevar8x32_ps(c, z_c);
      const __m256 dx = _mm256_sub_ps(px, _mm256_blend_ps(_mm256_blend_ps(xa, xb, 0x38), xc, 0xC0));
      const __m256 dy = _mm256_sub_ps(py, _mm256_blend_ps(_mm256_blend_ps(ya, yb, 0x18), yc, 0xE0));
      const __m256 dz = _mm256_sub_ps(pz, _mm256_blend_ps(_mm256_blend_ps(za, zb, 0x1C), zc, 0xE0));
      const __m256 r2 =
          _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)), _mm256_mul_ps(dz, dz));
      const int in = _mm256_movemask_ps(_mm256_cmp_ps(r2, reach2, _CMP_LT_OQ)) & ((1 << count) - 1);
      const __m256i to_front = _mm256_load_si256(reinterpret_cast<const __m256i*>(kPick.pick8[in]));
      const __m256i slot = _mm256_add_epi32(_mm256_set1_epi32(s), lane);
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(hit + n), _mm256_permutevar8x32_epi32(slot, to_front));
      _mm256_storeu_ps(hit_r2 + n, _mm256_permutevar8x32_ps(r2, to_front));
      n += __builtin_popcount(in);
    }
  return n;
}

// 4 positions per vector: 12 doubles in three loads; permutes by immediates and two blends.
MILLSIM_TARGET_AVX2 int filterAvx2(const int* begin, const int* end, int ranges, core::Vec3<double> p, double radius2,
                                   const core::Vec3<double>* pos, int* hit, double* hit_r2) {
  const __m256i lane64 = _mm256_setr_epi64x(0, 1, 2, 3);
  const __m128i lane = _mm_setr_epi32(0, 1, 2, 3);
  const __m256d px = _mm256_set1_pd(p.x), py = _mm256_set1_pd(p.y), pz = _mm256_set1_pd(p.z);
  const __m256d reach2 = _mm256_set1_pd(radius2);
  int n = 0;
  for (int k = 0; k < ranges; ++k)
    for (int s = begin[k], e = end[k]; s < e; s += 4) {
      const int count = e - s < 4 ? e - s : 4;
      const double* f = &pos[s].x;
      __m256d a, b, c;
      if (count == 4) {
        a = _mm256_loadu_pd(f), b = _mm256_loadu_pd(f + 4), c = _mm256_loadu_pd(f + 8);
      } else {
        const __m256i comps = _mm256_set1_epi64x(3 * count);
        a = _mm256_maskload_pd(f, _mm256_cmpgt_epi64(comps, lane64));
        b = _mm256_maskload_pd(f + 4, _mm256_cmpgt_epi64(comps, _mm256_add_epi64(lane64, _mm256_set1_epi64x(4))));
        c = _mm256_maskload_pd(f + 8, _mm256_cmpgt_epi64(comps, _mm256_add_epi64(lane64, _mm256_set1_epi64x(8))));
      }
      // x: a0 a3 b2 c1; y: a1 b0 b3 c2; z: a2 b1 c0 c3.
      const __m256d x =
          _mm256_blend_pd(_mm256_blend_pd(_mm256_permute4x64_pd(a, 0x0C), _mm256_permute4x64_pd(b, 0x20), 0x4),
                          _mm256_permute4x64_pd(c, 0x40), 0x8);
      const __m256d y =
          _mm256_blend_pd(_mm256_blend_pd(_mm256_permute4x64_pd(a, 0x01), _mm256_permute4x64_pd(b, 0x30), 0x6),
                          _mm256_permute4x64_pd(c, 0x80), 0x8);
      const __m256d z =
          _mm256_blend_pd(_mm256_blend_pd(_mm256_permute4x64_pd(a, 0x02), _mm256_permute4x64_pd(b, 0x04), 0x2),
                          _mm256_permute4x64_pd(c, 0xC0), 0xC);
      const __m256d dx = _mm256_sub_pd(px, x), dy = _mm256_sub_pd(py, y), dz = _mm256_sub_pd(pz, z);
      const __m256d r2 =
          _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)), _mm256_mul_pd(dz, dz));
      const int in = _mm256_movemask_pd(_mm256_cmp_pd(r2, reach2, _CMP_LT_OQ)) & ((1 << count) - 1);
      const __m128i slot = _mm_add_epi32(_mm_set1_epi32(s), lane);
      const __m256i to_front = _mm256_load_si256(reinterpret_cast<const __m256i*>(kPick.pick8[in]));
      const __m256i pairs_to_front = _mm256_load_si256(reinterpret_cast<const __m256i*>(kPick.pick_pairs4[in]));
      _mm_storeu_si128(reinterpret_cast<__m128i*>(hit + n),
                       _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(_mm256_castsi128_si256(slot), to_front)));
      _mm256_storeu_pd(hit_r2 + n, _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(r2), pairs_to_front)));
      n += __builtin_popcount(in);
    }
  return n;
}

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
  const backend::SimdLevel level = backend::simdLevel();
  if (level == backend::SimdLevel::kAvx512) return filterAvx512(begin, end, ranges, p, radius2, pos, hit, hit_r2);
  if (level == backend::SimdLevel::kAvx2) return filterAvx2(begin, end, ranges, p, radius2, pos, hit, hit_r2);
#endif
  return filterScalar(begin, end, ranges, p, radius2, pos, hit, hit_r2);
}

template int filterRangesInOrder<float>(const int*, const int*, int, core::Vec3<float>, float, const core::Vec3<float>*,
                                        int*, float*);
template int filterRangesInOrder<double>(const int*, const int*, int, core::Vec3<double>, double,
                                         const core::Vec3<double>*, int*, double*);

}  // namespace millsim::neighbors

#pragma once
// Two doubles at once on SSE2's two lanes, for the tests and decodings a
// ray does in pairs (bvh.h's boxes, shell_pair.h's shells, LevelShell's
// expand_pair). Each lane does the scalar code's operations in its order,
// so the results are its bits. Lane 0 is the first of a pair.
//
// Only where SSE2 is (every x86-64); callers fall back to their scalar code
// elsewhere.

#if defined(__SSE2__)

#include <emmintrin.h>

#include "subdivtrace/shell.h"

namespace subdivtrace::detail {

/// x in lane 0, y in lane 1.
inline __m128d pair_of(double x, double y) { return _mm_set_pd(y, x); }

/// All bits set in the lanes whose flag is true: a mask for select_lanes.
inline __m128d lane_mask(bool first, bool second) {
    return _mm_castsi128_pd(_mm_set_epi64x(second ? -1 : 0, first ? -1 : 0));
}

/// Per lane: mask ? yes : no.
inline __m128d select_lanes(__m128d mask, __m128d yes, __m128d no) {
    return _mm_or_pd(_mm_and_pd(mask, yes), _mm_andnot_pd(mask, no));
}

/// Lane 0 into `first`, lane 1 into `second`.
inline void store_lanes(__m128d v, double& first, double& second) {
    _mm_storel_pd(&first, v);
    _mm_storeh_pd(&second, v);
}

/// ray_box_interval (shell.h) on two boxes, lo[k] and hi[k] holding axis k's
/// bounds of both: narrows [t_near, t_far] per lane. Without the scalar
/// code's exit per axis: t_near only rises and t_far only falls, so the last
/// axis decides as the first failing one would. _mm_min_pd(x, y) is
/// x < y ? x : y and _mm_max_pd(x, y) x > y ? x : y, NaN giving y: the
/// scalar code's comparisons exactly (a ray lying in a box's face).
inline void ray_box_interval_pair(const RayBoxQuery& q, const __m128d* lo, const __m128d* hi, __m128d& t_near,
                                  __m128d& t_far) {
    const __m128d widen = _mm_set1_pd(1.0 + 2.0 * gamma_bound(3));
    for (int k = 0; k < 3; ++k) {
        const __m128d ray_origin = _mm_set1_pd(q.origin[k]);
        const __m128d inv_dir = _mm_set1_pd(q.inv_dir[k]);
        const __m128d t0 = _mm_mul_pd(_mm_sub_pd(lo[k], ray_origin), inv_dir);
        const __m128d t1 = _mm_mul_pd(_mm_sub_pd(hi[k], ray_origin), inv_dir);
        const __m128d nearer = _mm_min_pd(t1, t0);                     // t0 > t1 ? t1 : t0
        const __m128d farther = _mm_mul_pd(_mm_max_pd(t0, t1), widen);  // t0 > t1 ? t0 : t1
        t_near = _mm_max_pd(nearer, t_near);
        t_far = _mm_min_pd(farther, t_far);
    }
}

/// The verdicts of a pair of tests: a lane is entered unless `missed` is
/// set in it, and enters at its t_near.
inline void lane_verdicts(__m128d missed, __m128d t_near, bool& hit_a, bool& hit_b, double& t_a, double& t_b) {
    const int miss_bits = _mm_movemask_pd(missed);
    hit_a = (miss_bits & 1) == 0;
    hit_b = (miss_bits & 2) == 0;
    store_lanes(t_near, t_a, t_b);
}

}  // namespace subdivtrace::detail

#endif

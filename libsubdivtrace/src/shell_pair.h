#pragma once
// ray_hits_shell on two shells at once: a ray that enters a node tests its
// four children's shells, one by one about a fifth of the blob5k close-up.
// Where SSE2 is, each lane does ray_hits_shell's operations in its order,
// so the verdicts and entry distances are the same bits; elsewhere it is
// two calls of it.

#include "double_pairs.h"
#include "subdivtrace/shell.h"

namespace subdivtrace::detail {

inline void ray_hits_shell_pair(const RayBoxQuery& q, const Shell& a, const Shell& b, ShellKind kind,
                                bool& hit_a, bool& hit_b, double& t_a, double& t_b) {
#if defined(__SSE2__)
    const double g3 = 2.0 * gamma_bound(3);
    __m128d lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
        lo[k] = pair_of(a.lo[k], b.lo[k]);
        hi[k] = pair_of(a.hi[k], b.hi[k]);
    }
    __m128d t_near = _mm_set1_pd(q.t_min);
    __m128d t_far = _mm_set1_pd(q.t_max);
    ray_box_interval_pair(q, lo, hi, t_near, t_far);
    __m128d missed = _mm_cmpgt_pd(t_near, t_far);
    const bool slab_a = a.axis != Vec3(0.0), slab_b = b.axis != Vec3(0.0);
    if (kind == ShellKind::aabb_slab && (slab_a || slab_b) && _mm_movemask_pd(missed) != 3) {
        // The slab, in lanes whose shell has one: dot products summed x, y,
        // then z, as glm::dot does.
        const auto dot = [](const __m128d* x, const Vec3& y) {
            __m128d sum = _mm_mul_pd(x[0], _mm_set1_pd(y.x));
            sum = _mm_add_pd(sum, _mm_mul_pd(x[1], _mm_set1_pd(y.y)));
            return _mm_add_pd(sum, _mm_mul_pd(x[2], _mm_set1_pd(y.z)));
        };
        const __m128d axis[3] = {pair_of(a.axis.x, b.axis.x), pair_of(a.axis.y, b.axis.y),
                                 pair_of(a.axis.z, b.axis.z)};
        const __m128d denom = dot(axis, q.dir);
        const __m128d num = dot(axis, q.origin);
        // Rounding of the two dot products, bounded as in pbrt (|x| by
        // clearing the sign bit, as std::abs does).
        const __m128d magnitude = _mm_castsi128_pd(_mm_set1_epi64x(0x7fffffffffffffffLL));
        __m128d ao_sum = _mm_and_pd(_mm_mul_pd(axis[0], _mm_set1_pd(q.origin.x)), magnitude);
        ao_sum = _mm_add_pd(ao_sum, _mm_and_pd(_mm_mul_pd(axis[1], _mm_set1_pd(q.origin.y)), magnitude));
        ao_sum = _mm_add_pd(ao_sum, _mm_and_pd(_mm_mul_pd(axis[2], _mm_set1_pd(q.origin.z)), magnitude));
        const __m128d err = _mm_mul_pd(_mm_set1_pd(gamma_bound(5)), ao_sum);
        const __m128d s_min = _mm_sub_pd(pair_of(a.slab_min, b.slab_min), err);
        const __m128d s_max = _mm_add_pd(pair_of(a.slab_max, b.slab_max), err);
        // Parallel to the slab: inside it or not.
        const __m128d parallel = _mm_cmpeq_pd(denom, _mm_setzero_pd());
        const __m128d outside = _mm_or_pd(_mm_cmplt_pd(num, s_min), _mm_cmpgt_pd(num, s_max));
        // Otherwise the interval, each end widened away from zero.
        const __m128d t0 = _mm_div_pd(_mm_sub_pd(s_min, num), denom);
        const __m128d t1 = _mm_div_pd(_mm_sub_pd(s_max, num), denom);
        const __m128d lower = _mm_min_pd(t1, t0);
        const __m128d upper = _mm_max_pd(t0, t1);
        const __m128d shrink = _mm_set1_pd(1.0 - g3), grow = _mm_set1_pd(1.0 + g3);
        const __m128d lower_positive = _mm_cmpgt_pd(lower, _mm_setzero_pd());
        const __m128d upper_positive = _mm_cmpgt_pd(upper, _mm_setzero_pd());
        const __m128d slab_near = _mm_max_pd(_mm_mul_pd(lower, select_lanes(lower_positive, shrink, grow)), t_near);
        const __m128d slab_far = _mm_min_pd(_mm_mul_pd(upper, select_lanes(upper_positive, grow, shrink)), t_far);
        const __m128d slab_missed = select_lanes(parallel, outside, _mm_cmpgt_pd(slab_near, slab_far));
        const __m128d has_slab = lane_mask(slab_a, slab_b);
        // A slab that is crossed moves the entry (not where the ray runs parallel to it).
        t_near = select_lanes(_mm_andnot_pd(parallel, has_slab), slab_near, t_near);
        missed = _mm_or_pd(missed, _mm_and_pd(has_slab, slab_missed));
    }
    lane_verdicts(missed, t_near, hit_a, hit_b, t_a, t_b);
#else
    hit_a = ray_hits_shell(q, a, kind, t_a);
    hit_b = ray_hits_shell(q, b, kind, t_b);
#endif
}

}  // namespace subdivtrace::detail

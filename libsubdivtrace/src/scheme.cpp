// Stencils of the three schemes. Weights follow the sources named in scheme.h;
// Loop and Butterfly are written to match OpenMesh 9's LoopT and
// ModifiedButterflyT on closed meshes (tests/unit/test_schemes.cpp holds us to it).
#include "subdivtrace/scheme.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>

#include "corner_angle.h"
#include "scheme_rules.h"

// The normals' angle loops in a second, AVX2 build chosen at load time where
// the processor has it (four doubles a lane group instead of SSE2's two).
// AVX2 alone has no fused multiply-add, so both builds give the same bits.
// Not under the sanitizers: a ThreadSanitizer build crashes at start-up in
// the load-time chooser, which runs before its runtime is set up.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && \
    !defined(__SANITIZE_THREAD__) && !defined(__SANITIZE_ADDRESS__)
#define SUBDIVTRACE_WIDE_VECTORS __attribute__((target_clones("avx2", "default")))
#else
#define SUBDIVTRACE_WIDE_VECTORS
#endif

namespace subdivtrace {

namespace {

constexpr double k_pi = 3.14159265358979323846;

/// Neighbour `offset` steps counter-clockwise from index `from` in a ring, or
/// nullptr when an open fan ends before that.
const Vec3* ring_step(const VertexRing& ring, std::size_t from, long offset) {
    const long n = static_cast<long>(ring.nbrs.size());
    if (n == 0 || !ring.regular) return nullptr;
    long i = static_cast<long>(from) + offset;
    if (ring.closed) {
        i = ((i % n) + n) % n;
    } else if (i < 0 || i >= n) {
        return nullptr;
    }
    return &ring.nbrs[static_cast<std::size_t>(i)];
}

bool is_boundary_like(const VertexRing* ring) {
    return ring == nullptr || !ring->regular || !ring->closed;
}

std::size_t valence(const VertexRing* ring) { return ring ? ring->nbrs.size() : 0; }

/// Zorin's weights for an extraordinary interior vertex of valence k: s_j for
/// the neighbour j steps from the edge's other end, and the centre's weight.
double butterfly_weight(std::size_t k, std::size_t j) {
    if (k == 3) return j == 0 ? 5.0 / 12.0 : -1.0 / 12.0;
    if (k == 4) return j == 0 ? 3.0 / 8.0 : (j == 2 ? -1.0 / 8.0 : 0.0);
    const double inv_k = 1.0 / static_cast<double>(k);
    const double x = 2.0 * k_pi * static_cast<double>(j) * inv_k;
    return (0.25 + std::cos(x) + 0.5 * std::cos(2.0 * x)) * inv_k;
}

/// The extraordinary-vertex stencil of Zorin et al. around `center`, starting
/// at the edge's other endpoint (index `start`).
Vec3 butterfly_extraordinary(const VertexRing& ring, std::size_t start) {
    const std::size_t k = ring.nbrs.size();
    Vec3 sum(0.0);
    double weight_sum = 0.0;
    for (std::size_t j = 0; j < k; ++j) {
        const double w = butterfly_weight(k, j);
        sum += w * ring.nbrs[(start + j) % k];
        weight_sum += w;
    }
    return sum + (1.0 - weight_sum) * ring.center;
}

/// The wing across edge (x, y) of triangle (x, y, z): the ring's vertex if
/// there is one, else z mirrored through the edge's midpoint (as OpenMesh does).
Vec3 wing_or_mirror(const Vec3* wing, const Vec3& x, const Vec3& y, const Vec3& z) {
    return wing ? *wing : x + y - z;
}

}  // namespace

std::optional<SchemeKind> parse_scheme(const std::string& name) {
    for (SchemeKind kind : {SchemeKind::normal, SchemeKind::loop, SchemeKind::butterfly})
        if (name == detail::rules_of(kind).name) return kind;
    return std::nullopt;
}

const char* scheme_name(SchemeKind kind) { return detail::rules_of(kind).name; }

namespace {

double loop_alpha_of(std::size_t n) {
    const double t = 3.0 + 2.0 * std::cos(2.0 * k_pi / static_cast<double>(n));
    return (40.0 - t * t) / 64.0;
}

/// Loop's vertex weight, written once for the vertex rule and the limit
/// mask; common valences from a table, since every vertex of every level
/// asks for its own.
double loop_alpha(std::size_t n) {
    static const std::array<double, 32> table = [] {
        std::array<double, 32> t{};
        for (std::size_t k = 1; k < t.size(); ++k) t[k] = loop_alpha_of(k);
        return t;
    }();
    return n < table.size() ? table[n] : loop_alpha_of(n);
}

}  // namespace

Vec3 loop_vertex_point(const VertexRing& ring) {
    const std::size_t n = ring.nbrs.size();
    if (!ring.regular || n < 2 || ring.curve_count > 2) return ring.center;  // corners stay
    if (ring.curve_count == 2) {
        // Boundary or crease: the cubic B-spline rule along the curve (1-6-1).
        return (ring.center * 6.0 + ring.curve[0] + ring.curve[1]) * (1.0 / 8.0);
    }
    if (!ring.closed) return ring.center;
    const double inv_n = 1.0 / static_cast<double>(n);
    const double alpha = loop_alpha(n);
    Vec3 sum(0.0);
    for (const Vec3& q : ring.nbrs) sum += q;
    return sum * (inv_n * alpha) + (1.0 - alpha) * ring.center;
}

Vec3 loop_limit_point(const VertexRing& ring) {
    const std::size_t n = ring.nbrs.size();
    if (!ring.regular || n < 2 || ring.curve_count > 2) return ring.center;
    if (ring.curve_count == 2) return (ring.curve[0] + ring.center * 4.0 + ring.curve[1]) / 6.0;
    if (!ring.closed) return ring.center;
    const double alpha = loop_alpha(n);
    const double chi = 8.0 * alpha / (static_cast<double>(n) * (8.0 * alpha + 3.0));
    Vec3 sum(0.0);
    for (const Vec3& q : ring.nbrs) sum += q;
    return sum * chi + ring.center * (1.0 - static_cast<double>(n) * chi);
}

namespace {

/// The angle of ring point k of n in Loop's tangent masks.
double tangent_mask_angle(std::size_t k, std::size_t n) {
    return 2.0 * k_pi * static_cast<double>(k) / static_cast<double>(n);
}

/// cos and sin of tangent_mask_angle(k, n), k < n: common valences from a
/// table, since every vertex of every level a leaf shades at asks for its own.
struct TangentMasks {
    std::array<double, 16> cos{}, sin{};
};

TangentMasks tangent_masks_of(std::size_t n) {
    TangentMasks m;
    for (std::size_t k = 0; k < n && k < m.cos.size(); ++k) {
        m.cos[k] = std::cos(tangent_mask_angle(k, n));
        m.sin[k] = std::sin(tangent_mask_angle(k, n));
    }
    return m;
}

}  // namespace

Vec3 loop_limit_normal(const Vec3* ring, std::size_t n) {
    static const std::array<TangentMasks, 17> table = [] {
        std::array<TangentMasks, 17> t{};
        for (std::size_t k = 1; k < t.size(); ++k) t[k] = tangent_masks_of(k);
        return t;
    }();
    Vec3 t1(0.0), t2(0.0);
    for (std::size_t k = 0; k < n; ++k) {
        double c, s;
        if (n < table.size()) {
            c = table[n].cos[k];
            s = table[n].sin[k];
        } else {
            c = std::cos(tangent_mask_angle(k, n));
            s = std::sin(tangent_mask_angle(k, n));
        }
        t1 += c * ring[k];
        t2 += s * ring[k];
    }
    return finish_normal(glm::cross(t1, t2));
}

Vec3 normal_edge_point(const Vec3& a, const Vec3& b, const Vec3& na, const Vec3& nb) {
    // Midpoint of the cubic whose end tangents are the edge projected into each
    // endpoint's tangent plane (DESIGN.md section 3, our reconstruction of the
    // paper's reference [8]).
    const Vec3 d = b - a;
    return (a + b) * 0.5 + (glm::dot(d, nb) * nb - glm::dot(d, na) * na) * (1.0 / 8.0);
}

namespace {

/// d projected on the line through the origin along `dir` (d itself when dir is zero).
Vec3 project_on_line(const Vec3& d, const Vec3& dir) {
    const double len2 = glm::dot(dir, dir);
    if (!(len2 > 0.0) || !std::isfinite(len2)) return d;
    return dir * (glm::dot(d, dir) / len2);
}

}  // namespace

Vec3 normal_curve_edge_point(const EdgeStencil& s) {
    // Written so that swapping a and b gives the same bits: two meshes that
    // share a boundary may walk it in opposite directions.
    const Vec3 d = s.b - s.a;
    const Vec3 ta = s.has_a_far ? project_on_line(d, s.b - s.a_far)
                                : d - glm::dot(d, s.normal_a) * s.normal_a;
    const Vec3 tb = s.has_b_far ? project_on_line(d, s.b_far - s.a)
                                : d - glm::dot(d, s.normal_b) * s.normal_b;
    return (s.a + s.b) * 0.5 + (ta - tb) * (1.0 / 8.0);
}

Vec3 loop_edge_point(const EdgeStencil& s) {
    if (!s.interior || s.curve) return (s.a + s.b) * 0.5;
    return ((s.a + s.b) * 3.0 + s.c + s.d) * (1.0 / 8.0);
}

namespace {

/// The 8-point butterfly (1/2, 1/8, -1/16): butterfly_edge_point's regular
/// case, and the whole rule on a RegularEdge.
Vec3 butterfly_regular_edge_point(const detail::RegularEdge& e) {
    const Vec3 wings = e.w_bc + e.w_ac + e.w_bd + e.w_ad;
    return (e.a + e.b) * 0.5 + (e.c + e.d) * (1.0 / 8.0) + wings * (-1.0 / 16.0);
}

}  // namespace

Vec3 butterfly_edge_point(const EdgeStencil& s) {
    const VertexRing* ra = s.ring_a;
    const VertexRing* rb = s.ring_b;
    if (s.curve) {
        // Boundary or crease edge: the 4-point curve rule, using each
        // endpoint's other curve neighbour; straight where there is none.
        if (!s.has_a_far || !s.has_b_far) return (s.a + s.b) * 0.5;
        return (s.a + s.b) * (9.0 / 16.0) + (s.a_far + s.b_far) * (-1.0 / 16.0);
    }
    if (!s.interior) return (s.a + s.b) * 0.5;  // non-manifold

    const std::size_t va = valence(ra);
    const std::size_t vb = valence(rb);
    const bool a_boundary = is_boundary_like(ra);
    const bool b_boundary = is_boundary_like(rb);
    const bool a_extraordinary = !a_boundary && va != 6 && va >= 3;
    const bool b_extraordinary = !b_boundary && vb != 6 && vb >= 3;

    if (!a_extraordinary && !b_extraordinary) {
        // Regular case: the 8-point butterfly, with mirrored wings where a
        // ring is open or missing.
        const Vec3* w_ac = ra ? ring_step(*ra, s.index_b_in_a, 2) : nullptr;
        const Vec3* w_ad = ra ? ring_step(*ra, s.index_b_in_a, -2) : nullptr;
        const Vec3* w_bd = rb ? ring_step(*rb, s.index_a_in_b, 2) : nullptr;
        const Vec3* w_bc = rb ? ring_step(*rb, s.index_a_in_b, -2) : nullptr;
        return butterfly_regular_edge_point({s.a, s.b, s.c, s.d, wing_or_mirror(w_bc, s.b, s.c, s.a),
                                             wing_or_mirror(w_ac, s.a, s.c, s.b),
                                             wing_or_mirror(w_bd, s.b, s.d, s.a),
                                             wing_or_mirror(w_ad, s.a, s.d, s.b)});
    }

    // At least one extraordinary interior endpoint: its stencil, averaged over
    // both when both are extraordinary.
    Vec3 sum(0.0);
    double count = 0.0;
    if (a_extraordinary) {
        sum += butterfly_extraordinary(*ra, s.index_b_in_a);
        count += 1.0;
    }
    if (b_extraordinary) {
        sum += butterfly_extraordinary(*rb, s.index_a_in_b);
        count += 1.0;
    }
    return sum / count;
}

namespace {

/// The normal scheme's edge rule: the curve rule on a boundary or crease,
/// else from the endpoints' normals.
Vec3 normal_scheme_edge_point(const EdgeStencil& s) {
    return s.curve ? normal_curve_edge_point(s) : normal_edge_point(s.a, s.b, s.normal_a, s.normal_b);
}

constexpr detail::SchemeRules k_normal_rules{
    SchemeKind::normal, "normal", nullptr, normal_scheme_edge_point, normal_edge_point, nullptr, nullptr, nullptr,
    /*edge_rule_reads_normals=*/true, /*edge_rule_reads_opposites=*/false,
    /*edge_rule_reads_rings=*/false, /*convex_rules=*/false, /*takes_given_normals=*/true,
    /*sagitta_per_normal_offset=*/1.0};
constexpr detail::SchemeRules k_loop_rules{
    SchemeKind::loop, "loop", loop_vertex_point, loop_edge_point, nullptr, nullptr, loop_limit_point, loop_limit_normal,
    /*edge_rule_reads_normals=*/false, /*edge_rule_reads_opposites=*/true,
    /*edge_rule_reads_rings=*/false, /*convex_rules=*/true, /*takes_given_normals=*/false,
    /*sagitta_per_normal_offset=*/2.0};
constexpr detail::SchemeRules k_butterfly_rules{
    SchemeKind::butterfly, "butterfly", nullptr, butterfly_edge_point, nullptr, butterfly_regular_edge_point, nullptr, nullptr,
    /*edge_rule_reads_normals=*/false, /*edge_rule_reads_opposites=*/true,
    /*edge_rule_reads_rings=*/true, /*convex_rules=*/false, /*takes_given_normals=*/false,
    /*sagitta_per_normal_offset=*/1.0};

}  // namespace

const detail::SchemeRules& detail::rules_of(SchemeKind kind) {
    switch (kind) {
        case SchemeKind::normal: return k_normal_rules;
        case SchemeKind::loop: return k_loop_rules;
        case SchemeKind::butterfly: return k_butterfly_rules;
    }
    return k_normal_rules;
}

Vec3 edge_point(SchemeKind kind, const EdgeStencil& s) { return detail::rules_of(kind).edge_rule(s); }

Vec3 angle_weighted_normal(const Vec3& p, const Vec3& q, const Vec3& r) {
    const Vec3 e1 = q - p;
    const Vec3 e2 = r - p;
    const Vec3 n = glm::cross(e1, e2);
    const double len = glm::length(n);
    if (!(len > 0.0) || !std::isfinite(len)) return Vec3(0.0);
    // atan2 of |cross| and dot is accurate for tiny and near-straight angles,
    // where acos of a normalised dot is not.
    const double angle = detail::corner_angle(len, glm::dot(e1, e2));
    return n * (angle / len);
}

SUBDIVTRACE_WIDE_VECTORS
void angle_weighted_fan(const Vec3& centre, const Vec3* from, const Vec3* to, std::size_t count, Vec3* out) {
    // angle_weighted_normal's steps, eight triangles at a time: gather the
    // cross products, then the angles and scales in a loop without branches
    // (it vectorises), then the products.
    constexpr std::size_t k_block = 8;
    for (std::size_t start = 0; start < count; start += k_block) {
        const std::size_t n = std::min(k_block, count - start);
        Vec3 cross[k_block];
        double len[k_block], dot[k_block], scale[k_block];
        for (std::size_t k = 0; k < n; ++k) {
            const Vec3 e1 = from[start + k] - centre;
            const Vec3 e2 = to[start + k] - centre;
            cross[k] = glm::cross(e1, e2);
            len[k] = glm::length(cross[k]);
            dot[k] = glm::dot(e1, e2);
        }
        for (std::size_t k = 0; k < n; ++k) {
            const bool usable = (len[k] > 0.0) & (len[k] <= std::numeric_limits<double>::max());
            scale[k] = detail::corner_angle(len[k], dot[k]) / (usable ? len[k] : 1.0);
        }
        for (std::size_t k = 0; k < n; ++k) {
            // Tested again rather than kept from the loop above: storing
            // bools there stops that loop vectorising (GCC 12).
            const bool usable = (len[k] > 0.0) & (len[k] <= std::numeric_limits<double>::max());
            out[start + k] = usable ? cross[k] * scale[k] : Vec3(0.0);
        }
    }
}

SUBDIVTRACE_WIDE_VECTORS
void angle_weighted_corners(const Vec3* positions, const Triangle* triangles, std::size_t count,
                            Vec3* out) {
    // As angle_weighted_fan: gather, then the angles in a loop without
    // branches (it vectorises), then the products.
    constexpr std::size_t k_block = 8;
    for (std::size_t start = 0; start < count; start += k_block) {
        const std::size_t n = std::min(k_block, count - start);
        Vec3 cross[k_block];
        double len[k_block], dot0[k_block], dot1[k_block];
        double angle0[k_block], angle1[k_block], angle2[k_block];
        for (std::size_t k = 0; k < n; ++k) {
            const Triangle& tri = triangles[start + k];
            const Vec3& p0 = positions[tri[0]];
            const Vec3& p1 = positions[tri[1]];
            const Vec3& p2 = positions[tri[2]];
            cross[k] = glm::cross(p1 - p0, p2 - p0);
            len[k] = glm::length(cross[k]);
            dot0[k] = glm::dot(p1 - p0, p2 - p0);
            dot1[k] = glm::dot(p2 - p1, p0 - p1);
        }
        for (std::size_t k = 0; k < n; ++k) {
            angle0[k] = detail::corner_angle(len[k], dot0[k]);
            angle1[k] = detail::corner_angle(len[k], dot1[k]);
            // The angles sum to pi: the third costs no atan2, and differs
            // from its own by a few ulps of pi at most, far below what a
            // weight feels.
            angle2[k] = std::max(0.0, glm::pi<double>() - angle0[k] - angle1[k]);
        }
        for (std::size_t k = 0; k < n; ++k) {
            Vec3* corner = out + 3 * (start + k);
            if (!(len[k] > 0.0) || !(len[k] <= std::numeric_limits<double>::max())) {
                corner[0] = corner[1] = corner[2] = Vec3(0.0);
                continue;
            }
            const Vec3 unit = cross[k] / len[k];
            corner[0] = unit * angle0[k];
            corner[1] = unit * angle1[k];
            corner[2] = unit * angle2[k];
        }
    }
}

Vec3 finish_normal(const Vec3& sum) {
    const double len = glm::length(sum);
    if (!(len > 0.0) || !std::isfinite(len)) return Vec3(0.0);
    return sum / len;
}

}  // namespace subdivtrace

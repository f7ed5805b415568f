// The per-ray adaptive tracer (DESIGN.md sections 5 and 6): a top-level BVH
// over the base triangles' shells, then a descent through the lazy hierarchy
// in which every edge decides from its own endpoints and the ray's origin
// whether it refines. Midpoints of edges that do not refine snap to one of the
// edge's endpoints, so both sides of every edge draw the same segment and the
// surface each ray sees is closed.
#include "subdivtrace/tracer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "bvh.h"
#include "ray_triangle.h"
#include "subdivtrace/hierarchy.h"

namespace subdivtrace {

void TraceCounters::add(const TraceCounters& o) {
    rays += o.rays;
    nodes_visited += o.nodes_visited;
    leaves_tested += o.leaves_tested;
    cache_hits += o.cache_hits;
    cache_misses += o.cache_misses;
    deepest_level = std::max(deepest_level, o.deepest_level);
}

namespace {

/// A corner as the ray's surface draws it. Alive corners are the node's own
/// vertices; snapped ones were moved onto an endpoint of a frozen edge and
/// stay there for every descendant.
struct DrawnCorner {
    Vec3 position;
    Vec3 normal;
    Vec2 domain;  ///< barycentric weights of base corners 1 and 2
    bool alive;
};

/// What one all-hits hit met, for telling crossings apart by structure: the
/// drawn triangle's inside, one of its edges or one of its corners, named by
/// its drawn positions (bit-identical wherever leaves share them), and the
/// signed share of a full turn around the ray that this triangle covers there.
struct CrossingPart {
    std::array<Vec3, 3> feature;  ///< sorted corners; unused ones zero
    int corners;                  ///< 3 inside, 2 edge, 1 corner
    double turns;                 ///< +-1 inside, +-1/2 edge, +-angle/(2 pi) corner
    std::size_t hit;              ///< index into the hits
};

bool position_less(const Vec3& a, const Vec3& b) {
    return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : a.z < b.z;
}

bool feature_less(const CrossingPart& a, const CrossingPart& b) {
    if (a.corners != b.corners) return a.corners < b.corners;
    for (int c = 0; c < a.corners; ++c) {
        if (position_less(a.feature[c], b.feature[c])) return true;
        if (position_less(b.feature[c], a.feature[c])) return false;
    }
    return false;
}

Vec2 grid_domain(const NodeId& id, int corner) {
    const auto g = node_corner_grid(id)[corner];
    const double inv_n = 1.0 / static_cast<double>(std::uint64_t{1} << id.level);
    return Vec2(g[0] * inv_n, g[1] * inv_n);
}

void check_options(const SurfaceOptions& o) {
    if (!(o.tolerance > 0.0) || !std::isfinite(o.tolerance))
        throw std::invalid_argument("tolerance must be a positive number, got " +
                                    std::to_string(o.tolerance));
    if (o.max_level < 0 || o.max_level > k_max_level_cap)
        throw std::invalid_argument("max_level must be in 0.." + std::to_string(k_max_level_cap) +
                                    ", got " + std::to_string(o.max_level));
    if (o.cache_mb < 1) throw std::invalid_argument("cache_mb must be at least 1");
    AdaptiveSurface::check_view(o.view);
}

}  // namespace

void AdaptiveSurface::check_view(const View& v) {
    if (v.orthographic ? !(v.pixel_size > 0.0 && std::isfinite(v.pixel_size))
                       : !(v.pixel_angle > 0.0 && std::isfinite(v.pixel_angle)))
        throw std::invalid_argument("the view's pixel size/angle must be positive and finite");
    if (!std::isfinite(v.camera.x) || !std::isfinite(v.camera.y) || !std::isfinite(v.camera.z))
        throw std::invalid_argument("the camera position must be finite");
}

namespace {

/// Every surface gets an id never reused, so per-thread caches cannot
/// confuse a destroyed surface with a new one at the same address.
std::atomic<std::uint64_t> g_next_surface_id{1};

/// The mesh as the surface keeps it: arrays at their size. (Its corner
/// normals go once the hierarchy has read them: it keeps what it needs of
/// them compactly, and they would cost 72 bytes per triangle.)
Mesh as_kept(Mesh m) {
    m.positions.shrink_to_fit();
    m.triangles.shrink_to_fit();
    m.corner_normals.shrink_to_fit();
    m.corner_uvs.shrink_to_fit();
    return m;
}

}  // namespace

class SurfaceImpl {
public:
    SurfaceImpl(Mesh m, const SurfaceOptions& o)
        : mesh(as_kept(std::move(m))),
          options(o),
          hierarchy(mesh, o.scheme, o.max_level, o.cache_mb << 20, o.shell_kind) {
        mesh.corner_normals = std::vector<Vec3>();  // read by the hierarchy's construction only
        std::vector<Vec3> lo, hi;
        for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f) {
            const Shell shell = hierarchy.node(Hierarchy::root(f)).shell;
            lo.push_back(shell.lo);
            hi.push_back(shell.hi);
            bounds.lo = f == 0 ? lo.back() : glm::min(bounds.lo, lo.back());
            bounds.hi = f == 0 ? hi.back() : glm::max(bounds.hi, hi.back());
        }
        top.build(lo, hi, 2);
        level_histogram = std::vector<std::atomic<std::uint64_t>>(k_max_level_cap + 1);
    }

    void trace(const Ray& ray, bool all, Hit* nearest, bool* found, std::vector<Hit>* hits,
               TraceCounters* counters) const;
    void collect_drawn(const Vec3& origin, double origin_distance,
                       std::vector<std::array<Vec3, 3>>& out) const;

    Mesh mesh;
    SurfaceOptions options;
    Hierarchy hierarchy;
    detail::Bvh top;
    Bounds3 bounds;
    const std::uint64_t id = g_next_surface_id.fetch_add(1);
    mutable std::vector<std::atomic<std::uint64_t>> level_histogram;
    /// Running totals, relaxed atomics: no ray waits on another for them.
    struct Totals {
        std::atomic<std::uint64_t> rays{0}, nodes_visited{0}, leaves_tested{0};
        std::atomic<int> deepest_level{0};
        void add(const TraceCounters& c) {
            rays.fetch_add(c.rays, std::memory_order_relaxed);
            nodes_visited.fetch_add(c.nodes_visited, std::memory_order_relaxed);
            leaves_tested.fetch_add(c.leaves_tested, std::memory_order_relaxed);
            int seen = deepest_level.load(std::memory_order_relaxed);
            while (c.deepest_level > seen &&
                   !deepest_level.compare_exchange_weak(seen, c.deepest_level,
                                                        std::memory_order_relaxed)) {
            }
        }
    };
    mutable Totals totals;
};

namespace {

/// One ray's walk through the hierarchy.
struct Traversal {
    const SurfaceImpl& s;
    const View& view;
    Vec3 origin;
    Vec3 dir;
    double origin_distance;  ///< D: camera to origin along the light path
    double t_min;
    double t_max;  ///< shrinks to the nearest hit in nearest mode
    bool collect_all;
    RayBoxQuery query;
    detail::WatertightRay wray;
    Hit best;
    bool found = false;
    std::vector<Hit>* all_hits = nullptr;
    TraceCounters counters;
    /// Diagnostics mode: no culling, leaves collected instead of intersected.
    std::vector<std::array<Vec3, 3>>* drawn_out = nullptr;
    /// All-hits mode: what each hit met, parallel to *all_hits.
    std::vector<CrossingPart> parts;

    /// DESIGN section 5: an edge refines while it is longer than the ray's
    /// footprint where the ray would meet it, width(d) = angle * (D + d) * tol.
    bool edge_refines(const Vec3& a, const Vec3& b) const {
        const double length = glm::length(b - a);
        double width;
        if (view.orthographic) {
            width = view.pixel_size * s.options.tolerance;
        } else {
            const double to_mid = glm::length((a + b) * 0.5 - origin);
            const double d = std::max(0.0, to_mid - 0.5 * length);
            width = view.pixel_angle * (origin_distance + d) * s.options.tolerance;
        }
        return length > width;
    }

    bool shell_entry(const Shell& shell, const DrawnCorner* drawn, double& t_entry) const {
        if (drawn_out) {
            t_entry = 0.0;
            return true;
        }
        RayBoxQuery q = query;
        q.t_max = t_max;
        if (drawn[0].alive && drawn[1].alive && drawn[2].alive)
            return ray_hits_shell(q, shell, s.options.shell_kind, t_entry);
        // Snapped corners can lie outside the node's own shell: grow by them.
        Shell grown = shell;
        for (int c = 0; c < 3; ++c)
            if (!drawn[c].alive) grown.grow_both(drawn[c].position);
        return ray_hits_shell(q, grown, s.options.shell_kind, t_entry);
    }

    void leaf(const NodeId& id, const NodeRecord& rec, const DrawnCorner* drawn,
              double parent_thickness) {
        ++counters.leaves_tested;
        if (drawn_out) {
            drawn_out->push_back({drawn[0].position, drawn[1].position, drawn[2].position});
            return;
        }
        detail::TriangleHit th;
        if (!detail::intersect_watertight(wray, drawn[0].position, drawn[1].position,
                                          drawn[2].position, t_min, t_max, th))
            return;
        Hit h;
        h.t = th.t;
        h.point = th.b0 * drawn[0].position + th.b1 * drawn[1].position + th.b2 * drawn[2].position;
        h.geometric_normal = finish_normal(glm::cross(drawn[1].position - drawn[0].position,
                                                      drawn[2].position - drawn[0].position));
        h.normal = finish_normal(th.b0 * drawn[0].normal + th.b1 * drawn[1].normal +
                                 th.b2 * drawn[2].normal);
        if (h.normal == Vec3(0.0)) h.normal = h.geometric_normal;
        const Vec2 w = th.b0 * drawn[0].domain + th.b1 * drawn[1].domain + th.b2 * drawn[2].domain;
        if (s.mesh.has_uvs()) {
            const Vec2* uv = &s.mesh.corner_uvs[3 * std::size_t{id.face}];
            h.uv = (1.0 - w.x - w.y) * uv[0] + w.x * uv[1] + w.y * uv[2];
        } else {
            h.uv = w;
        }
        h.triangle = {drawn[0].position, drawn[1].position, drawn[2].position};
        h.level = id.level;
        h.base_face = id.face;
        // Rounding of the hit point, plus how far the surface another ray sees
        // here may lie from this leaf. A finer one stays in the leaf's shell,
        // snapping moves it to the drawn corners, and a ray that stops one
        // level coarser (a secondary ray from this point judges edges by their
        // distance from the point, not from the camera) sees the parent,
        // inside the parent's shell: the larger thickness bounds them all.
        Shell grown = rec.shell;
        for (int c = 0; c < 3; ++c) grown.grow_both(drawn[c].position);
        const Vec3 ap = glm::abs(h.point);
        h.error_bound = gamma_bound(7) * (ap.x + ap.y + ap.z) +
                        std::max({0.0, grown.thickness(), parent_thickness});
        if (collect_all) {
            parts.push_back(crossing_part(h.triangle, th, all_hits->size()));
            all_hits->push_back(h);
        } else {
            best = h;
            found = true;
            t_max = h.t;
        }
    }

    /// The feature of the leaf the ray met and the share of a turn around the
    /// ray the leaf covers there. Zero weights are exact (the watertight test
    /// computes a shared edge's function identically from both sides), so
    /// every leaf that meets the same edge or corner names the same feature.
    CrossingPart crossing_part(const std::array<Vec3, 3>& t, const detail::TriangleHit& th,
                               std::size_t hit) const {
        constexpr double k_two_pi = 6.283185307179586476925;
        const double b[3] = {th.b0, th.b1, th.b2};
        const double sign = th.det > 0.0 ? 1.0 : -1.0;
        CrossingPart part{{Vec3(0.0), Vec3(0.0), Vec3(0.0)}, 0, 0.0, hit};
        for (int c = 0; c < 3; ++c)
            if (b[c] != 0.0) part.feature[part.corners++] = t[c];
        // At most three: sorted by hand (std::sort here trips GCC 12's -Warray-bounds).
        auto order = [&](int x, int y) {
            if (position_less(part.feature[y], part.feature[x]))
                std::swap(part.feature[x], part.feature[y]);
        };
        if (part.corners >= 2) order(0, 1);
        if (part.corners == 3) {
            order(1, 2);
            order(0, 1);
        }
        if (part.corners == 3) {
            part.turns = sign;
        } else if (part.corners == 2) {
            part.turns = 0.5 * sign;
        } else {
            // The corner's angle in the plane across the ray (the test's shear).
            const int i = b[0] != 0.0 ? 0 : b[1] != 0.0 ? 1 : 2;
            auto project = [&](const Vec3& p) {
                const Vec3 q = p - wray.origin;
                return Vec2(q[wray.kx] - wray.sx * q[wray.kz], q[wray.ky] - wray.sy * q[wray.kz]);
            };
            const Vec2 o = project(t[i]);
            const Vec2 u = project(t[(i + 1) % 3]) - o, v = project(t[(i + 2) % 3]) - o;
            const double angle = std::atan2(std::abs(u.x * v.y - u.y * v.x), u.x * v.x + u.y * v.y);
            part.turns = sign * angle / k_two_pi;
        }
        return part;
    }

    /// Starts the descent at a base triangle: its corners and edges are its own.
    void visit_root(std::uint32_t face) {
        const NodeId id = Hierarchy::root(face);
        const NodeRecord rec = s.hierarchy.node(id);
        DrawnCorner drawn[3];
        for (int c = 0; c < 3; ++c)
            drawn[c] = {rec.draw_position[c], rec.normal[c], grid_domain(id, c), true};
        double t_entry;
        if (!shell_entry(rec.shell, drawn, t_entry)) return;
        const bool exists[3] = {true, true, true};
        visit(id, rec, drawn, exists, 0.0);
    }

    void visit(const NodeId& id, const NodeRecord& rec, const DrawnCorner* drawn,
               const bool* edge_exists, double parent_thickness) {
        ++counters.nodes_visited;
        counters.deepest_level = std::max(counters.deepest_level, int{id.level});
        const bool naive = s.options.crack_rule == CrackRule::per_triangle;
        bool refine[3];
        bool any = false;
        for (int e = 0; e < 3; ++e) {
            refine[e] = edge_exists[e] && id.level < s.options.max_level &&
                        edge_refines(rec.position[e], rec.position[(e + 1) % 3]);
            any = any || refine[e];
        }
        // The paper's rule: the triangle alone decides and every child vertex
        // is its own (T-junctions wherever neighbours disagree).
        if (naive) refine[0] = refine[1] = refine[2] = any;
        if (!any) {
            leaf(id, rec, drawn, parent_thickness);
            return;
        }

        // A triangle refines if any of its edges does (section 6). The
        // midpoint of a frozen edge snaps to one of its endpoints; either way
        // this side draws the whole segment, so each side may choose: towards
        // the corner where another frozen edge meets it, which tiles the
        // triangle as a fan from that corner instead of leaving a sliver
        // between the chord and a refined neighbour edge.
        int snap_to[3];
        for (int e = 0; e < 3; ++e) {
            const int a = e, b = (e + 1) % 3;
            const bool frozen_at_a = !refine[(e + 2) % 3];
            const bool frozen_at_b = !refine[(e + 1) % 3];
            snap_to[e] = frozen_at_a || !frozen_at_b ? a : b;
        }
        const double thickness = rec.shell.thickness();
        struct Child {
            NodeId id;
            DrawnCorner drawn[3];
            bool exists[3];
            double t_entry;
            bool hit;
        };
        Child children[4];
        std::array<NodeRecord, 4> child_recs;
        s.hierarchy.children(id, child_recs);
        for (int c = 0; c < 4; ++c) {
            Child& ch = children[c];
            ch.id = child_of(id, c);
            const NodeRecord& child_rec = child_recs[c];
            const auto& map = child_corners(id.down, c);
            for (int k = 0; k < 3; ++k) {
                const ChildCorner cc = map[k];
                const bool own =
                    naive || (cc.is_edge ? refine[cc.index] : drawn[cc.index].alive);
                if (own) {
                    ch.drawn[k] = {child_rec.draw_position[k], child_rec.normal[k],
                                   grid_domain(ch.id, k), true};
                } else if (!cc.is_edge) {
                    ch.drawn[k] = drawn[cc.index];
                } else {
                    ch.drawn[k] = drawn[snap_to[cc.index]];
                    ch.drawn[k].alive = false;
                }
            }
            for (int k = 0; k < 3; ++k) {
                const ChildCorner p = map[k], q = map[(k + 1) % 3];
                // Halves of a parent edge exist only if that edge refined.
                if (naive) ch.exists[k] = true;
                else if (!p.is_edge) ch.exists[k] = refine[q.index];
                else if (!q.is_edge) ch.exists[k] = refine[p.index];
                else ch.exists[k] = true;
            }
            ch.hit = shell_entry(child_rec.shell, ch.drawn, ch.t_entry);
        }
        int order[4] = {0, 1, 2, 3};
        std::sort(order, order + 4, [&](int x, int y) {
            const double tx = children[x].hit ? children[x].t_entry : 1e300;
            const double ty = children[y].hit ? children[y].t_entry : 1e300;
            return tx < ty;
        });
        for (int k = 0; k < 4; ++k) {
            Child& ch = children[order[k]];
            if (!ch.hit) break;
            if (!collect_all && !drawn_out && ch.t_entry > t_max) break;
            visit(ch.id, child_recs[order[k]], ch.drawn, ch.exists, thickness);
        }
    }
};

}  // namespace

namespace {

/// Each crossing once, by structure (docs/tracer.md section 3): the hits on one
/// feature (a drawn triangle's inside, edge or corner) are one place where the
/// ray meets the surface, crossed as many times as the triangles there wind
/// around the ray (their signed turns, summed and rounded). A shared edge or
/// corner the ray passes through winds once: one crossing. A triangle the
/// snapped rule draws twice, once each way round (the double layer), and a
/// silhouette edge or corner the ray only touches wind zero times: no crossing.
/// A ray running along a drawn edge meets its two corners with part of each
/// fan edge-on (no hit); their windings then add up to a whole number, so
/// rounding each to the nearest keeps the parity of the pair.
void merge_crossings(std::vector<CrossingPart>& parts, std::vector<Hit>& hits) {
    std::sort(parts.begin(), parts.end(), feature_less);
    std::vector<Hit> out;
    out.reserve(hits.size());
    for (std::size_t first = 0; first < parts.size();) {
        std::size_t end = first + 1;
        while (end < parts.size() && !feature_less(parts[first], parts[end])) ++end;
        double turns = 0.0;
        for (std::size_t k = first; k < end; ++k) turns += parts[k].turns;
        const long crossings = std::lround(std::abs(turns));
        // Report the hit of a triangle facing the way the crossing goes.
        std::size_t pick = first;
        for (std::size_t k = first; k < end; ++k)
            if ((parts[k].turns > 0.0) == (turns > 0.0)) {
                pick = k;
                break;
            }
        for (long c = 0; c < crossings; ++c) out.push_back(hits[parts[pick].hit]);
        first = end;
    }
    std::sort(out.begin(), out.end(), [](const Hit& a, const Hit& b) { return a.t < b.t; });
    hits.swap(out);
}

}  // namespace

void SurfaceImpl::trace(const Ray& ray, bool all, Hit* nearest, bool* found,
                        std::vector<Hit>* hits, TraceCounters* counters) const {
    const double dir_length = glm::length(ray.direction);
    if (!(dir_length > 0.0) || !std::isfinite(dir_length) || !std::isfinite(ray.origin.x) ||
        !std::isfinite(ray.origin.y) || !std::isfinite(ray.origin.z)) {
        if (found) *found = false;
        return;
    }
    const View& view = ray.view ? *ray.view : options.view;
    Traversal tr{*this,
                 view,
                 ray.origin,
                 ray.direction,
                 ray.origin_distance >= 0.0 ? ray.origin_distance
                                            : glm::length(ray.origin - view.camera),
                 ray.t_min,
                 ray.t_max,
                 all,
                 make_ray_box_query(ray.origin, ray.direction, ray.t_min, ray.t_max),
                 detail::make_watertight_ray(ray.origin, ray.direction),
                 Hit{},
                 false,
                 hits,
                 TraceCounters{},
                 nullptr,
                 {}};
    tr.counters.rays = 1;
    top.traverse(tr.query, tr.t_max, [&](std::uint32_t face) { tr.visit_root(face); });
    if (found) *found = tr.found;
    if (nearest && tr.found) *nearest = tr.best;
    if (tr.found) level_histogram[tr.best.level].fetch_add(1, std::memory_order_relaxed);
    if (all && hits) {
        merge_crossings(tr.parts, *hits);
        for (const Hit& h : *hits) level_histogram[h.level].fetch_add(1, std::memory_order_relaxed);
    }
    if (counters) counters->add(tr.counters);
    totals.add(tr.counters);
}

void SurfaceImpl::collect_drawn(const Vec3& origin, double origin_distance,
                                std::vector<std::array<Vec3, 3>>& out) const {
    Traversal tr{*this,
                 options.view,
                 origin,
                 Vec3(0.0, 0.0, 1.0),
                 origin_distance,
                 0.0,
                 1e300,
                 true,
                 make_ray_box_query(origin, Vec3(0.0, 0.0, 1.0), 0.0, 1e300),
                 detail::make_watertight_ray(origin, Vec3(0.0, 0.0, 1.0)),
                 Hit{},
                 false,
                 nullptr,
                 TraceCounters{},
                 &out,
                 {}};
    for (std::uint32_t face = 0; face < mesh.triangles.size(); ++face) tr.visit_root(face);
}

AdaptiveSurface::AdaptiveSurface(Mesh mesh, const SurfaceOptions& options) {
    check_options(options);
    validate_mesh(mesh, "mesh");
    impl_ = std::make_unique<SurfaceImpl>(std::move(mesh), options);
}

AdaptiveSurface::~AdaptiveSurface() = default;

bool AdaptiveSurface::intersect(const Ray& ray, Hit& hit, TraceCounters* counters) const {
    bool found = false;
    impl_->trace(ray, false, &hit, &found, nullptr, counters);
    return found;
}

void AdaptiveSurface::intersect_all(const Ray& ray, std::vector<Hit>& hits,
                                    TraceCounters* counters) const {
    hits.clear();
    impl_->trace(ray, true, nullptr, nullptr, &hits, counters);
}

bool AdaptiveSurface::inside(const Vec3& point, const View* view) const {
    // A fixed direction no axis-aligned or symmetric mesh lines up with.
    Ray ray;
    ray.view = view;
    ray.origin = point;
    ray.direction = glm::normalize(Vec3(0.4812, 0.6029, 0.6366));
    std::vector<Hit> hits;
    intersect_all(ray, hits);
    return hits.size() % 2 == 1;
}

void AdaptiveSurface::drawn_triangles(const Vec3& origin, double origin_distance,
                                      std::vector<std::array<Vec3, 3>>& out) const {
    out.clear();
    impl_->collect_drawn(origin, origin_distance, out);
}

Bounds3 AdaptiveSurface::bounds() const { return impl_->bounds; }
bool AdaptiveSurface::is_closed() const { return impl_->hierarchy.closed(); }
const SurfaceOptions& AdaptiveSurface::options() const { return impl_->options; }

void AdaptiveSurface::set_view(const View& view) {
    SurfaceOptions o = impl_->options;
    o.view = view;
    check_options(o);
    impl_->options.view = view;
}

SurfaceStats AdaptiveSurface::stats() const {
    SurfaceStats s;
    s.trace.rays = impl_->totals.rays.load();
    s.trace.nodes_visited = impl_->totals.nodes_visited.load();
    s.trace.leaves_tested = impl_->totals.leaves_tested.load();
    s.trace.deepest_level = impl_->totals.deepest_level.load();
    const HierarchyCounters h = impl_->hierarchy.counters();
    s.trace.cache_hits = h.node_hits;
    s.trace.cache_misses = h.node_misses;
    s.nodes_built = h.nodes_built;
    s.cache_evictions = h.evictions;
    s.cache_bytes = h.bytes;
    s.cache_peak_bytes = h.peak_bytes;
    const Mesh& m = impl_->mesh;
    s.memory.mesh = m.positions.capacity() * sizeof(Vec3) + m.triangles.capacity() * sizeof(Triangle) +
                    m.corner_normals.capacity() * sizeof(Vec3) + m.corner_uvs.capacity() * sizeof(Vec2);
    s.memory.topology = h.topology_bytes;
    s.memory.bvh = impl_->top.memory_bytes();
    s.memory.roots = h.root_bytes;
    s.memory.fronts = h.front_bytes;
    s.memory.front_threads = h.fronts;
    s.base_triangles = m.triangles.size();
    for (const auto& c : impl_->level_histogram) s.leaf_level_histogram.push_back(c.load());
    while (!s.leaf_level_histogram.empty() && s.leaf_level_histogram.back() == 0)
        s.leaf_level_histogram.pop_back();
    return s;
}

std::uint64_t AdaptiveSurface::uniform_triangle_count(int level) const {
    return static_cast<std::uint64_t>(impl_->mesh.triangles.size()) << (2 * level);
}

}  // namespace subdivtrace

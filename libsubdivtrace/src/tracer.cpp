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
#include <cstring>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "bvh.h"
#include "crossings.h"
#include "huge_pages.h"
#include "ray_triangle.h"
#include "shell_pair.h"
#include "subdivtrace/hierarchy.h"

namespace subdivtrace {

void TraceCounters::add(const TraceCounters& o) {
    rays += o.rays;
    nodes_visited += o.nodes_visited;
    leaves_tested += o.leaves_tested;
    cache_hits += o.cache_hits;
    cache_misses += o.cache_misses;
    deepest_level = std::max(deepest_level, o.deepest_level);
    hits += o.hits;
    error_bound_px_sum += o.error_bound_px_sum;
    error_bound_px_max = std::max(error_bound_px_max, o.error_bound_px_max);
    hits_at_max_level += o.hits_at_max_level;
}

const char* refine_rule_name(RefineRule rule) {
    return rule == RefineRule::size ? "size" : "error";
}

bool parse_refine_rule(const std::string& text, RefineRule& rule) {
    if (text == "error") rule = RefineRule::error;
    else if (text == "size") rule = RefineRule::size;
    else return false;
    return true;
}

namespace {

/// A corner as the ray's surface draws it. Alive corners are the node's own
/// vertices; snapped ones were moved onto an endpoint of a frozen edge and
/// stay there for every descendant.
struct DrawnCorner {
    Vec3 position;
    /// Whose corner it is: the record that holds its shading normal, and
    /// its grid point (grid_domain). Read only for the leaf a ray hits (the
    /// descent reads records without normals, and a ray enters most nodes
    /// without hitting them: the domain computed at every corner met was
    /// 1.8% of a close-up).
    NodeId normal_node;
    int normal_corner;
    bool alive;
};

/// The barycentric weights of base corners 1 and 2 at corner `corner` of `id`.
Vec2 grid_domain(const NodeId& id, int corner) {
    const auto g = node_corner_grid(id)[corner];
    // 2^-level, written as its exponent bits: exactly 1 / 2^level, without
    // a division at every corner a ray meets.
    const std::uint64_t bits = static_cast<std::uint64_t>(1023 - id.level) << 52;
    double inv_n;
    std::memcpy(&inv_n, &bits, sizeof inv_n);
    return Vec2(g[0] * inv_n, g[1] * inv_n);
}

void check_options(const SurfaceOptions& o) {
    if (!(o.tolerance > 0.0) || !std::isfinite(o.tolerance))
        throw std::invalid_argument("tolerance must be a positive number, got " +
                                    std::to_string(o.tolerance));
    if (o.max_level < 0 || o.max_level > k_max_level_cap)
        throw std::invalid_argument("max_level must be in 0.." + std::to_string(k_max_level_cap) +
                                    ", got " + std::to_string(o.max_level));
    if (!o.cache && o.cache_mb < 1) throw std::invalid_argument("cache_mb must be at least 1");
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
          hierarchy(mesh, o.scheme, o.max_level,
                    o.cache ? o.cache : std::make_shared<TileCache>(o.cache_mb << 20), o.shell_kind) {
        options.cache = hierarchy.cache();
        mesh.corner_normals = std::vector<Vec3>();  // read by the hierarchy's construction only
        std::vector<Vec3> lo, hi;
        detail::reserve_huge(lo, mesh.triangles.size());
        detail::reserve_huge(hi, mesh.triangles.size());
        for (std::uint32_t f = 0; f < mesh.triangles.size(); ++f) {
            const Shell shell = hierarchy.root_shell(f);
            lo.push_back(shell.lo);
            hi.push_back(shell.hi);
            bounds.lo = f == 0 ? lo.back() : glm::min(bounds.lo, lo.back());
            bounds.hi = f == 0 ? hi.back() : glm::max(bounds.hi, hi.back());
        }
        top.build(std::move(lo), std::move(hi), 2);
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
    /// Running totals, relaxed atomics: no ray waits on another for them.
    /// One set per thread slot (a thread keeps its slot), each on cache
    /// lines of its own: a ray adds to seven of them, and threads adding to
    /// one shared set passed its cache lines back and forth at every ray.
    struct alignas(64) Totals {
        std::atomic<std::uint64_t> rays{0}, nodes_visited{0}, leaves_tested{0};
        std::atomic<std::uint64_t> hits{0}, hits_at_max_level{0};
        std::atomic<int> deepest_level{0};
        std::atomic<double> error_bound_px_sum{0.0}, error_bound_px_max{0.0};
        std::array<std::atomic<std::uint64_t>, k_max_level_cap + 1> level_histogram{};
        void add(const TraceCounters& c) {
            rays.fetch_add(c.rays, std::memory_order_relaxed);
            nodes_visited.fetch_add(c.nodes_visited, std::memory_order_relaxed);
            leaves_tested.fetch_add(c.leaves_tested, std::memory_order_relaxed);
            hits.fetch_add(c.hits, std::memory_order_relaxed);
            hits_at_max_level.fetch_add(c.hits_at_max_level, std::memory_order_relaxed);
            raise_to(deepest_level, c.deepest_level);
            raise_to(error_bound_px_max, c.error_bound_px_max);
            if (c.error_bound_px_sum != 0.0) {
                double sum = error_bound_px_sum.load(std::memory_order_relaxed);
                while (!error_bound_px_sum.compare_exchange_weak(sum, sum + c.error_bound_px_sum,
                                                                 std::memory_order_relaxed)) {
                }
            }
        }
        /// The counters this slot holds (cache hits and misses are the hierarchy's).
        TraceCounters snapshot() const {
            TraceCounters c;
            c.rays = rays.load(std::memory_order_relaxed);
            c.nodes_visited = nodes_visited.load(std::memory_order_relaxed);
            c.leaves_tested = leaves_tested.load(std::memory_order_relaxed);
            c.hits = hits.load(std::memory_order_relaxed);
            c.hits_at_max_level = hits_at_max_level.load(std::memory_order_relaxed);
            c.deepest_level = deepest_level.load(std::memory_order_relaxed);
            c.error_bound_px_sum = error_bound_px_sum.load(std::memory_order_relaxed);
            c.error_bound_px_max = error_bound_px_max.load(std::memory_order_relaxed);
            return c;
        }
        template <class T>
        static void raise_to(std::atomic<T>& target, T value) {
            T seen = target.load(std::memory_order_relaxed);
            while (value > seen &&
                   !target.compare_exchange_weak(seen, value, std::memory_order_relaxed)) {
            }
        }
    };
    static constexpr std::size_t k_total_slots = 16;
    mutable std::array<Totals, k_total_slots> totals;
    /// The calling thread's set of totals.
    Totals& my_totals() const {
        static std::atomic<std::size_t> next_slot{0};
        thread_local const std::size_t slot = next_slot.fetch_add(1, std::memory_order_relaxed) % k_total_slots;
        return totals[slot];
    }
    /// The totals summed over every thread's.
    TraceCounters summed_totals(std::vector<std::uint64_t>& histogram) const {
        TraceCounters sum;
        histogram.assign(k_max_level_cap + 1, 0);
        for (const Totals& t : totals) {
            sum.add(t.snapshot());
            for (std::size_t l = 0; l < histogram.size(); ++l) histogram[l] += t.level_histogram[l].load();
        }
        return sum;
    }
};

namespace {

/// What a walk does with the leaves it reaches.
enum class WalkMode {
    nearest,   ///< intersect, keep the closest hit, stop behind it
    all_hits,  ///< intersect, keep every hit (CSG); merged into crossings after
    drawn,     ///< diagnostics: no culling, every leaf collected as drawn
};

/// Where a walk starts and what it is for: named fields instead of a long
/// positional initialiser.
struct WalkSetup {
    const View* view = nullptr;
    Vec3 origin{0.0};
    Vec3 direction{0.0, 0.0, 1.0};
    double origin_distance = 0.0;  ///< D: camera to origin along the light path
    double t_min = 0.0;
    double t_max = 1e300;
    WalkMode mode = WalkMode::nearest;
    std::vector<Hit>* all_hits = nullptr;                  ///< all_hits mode
    std::vector<std::array<Vec3, 3>>* drawn_out = nullptr;  ///< drawn mode
};

/// The error rule's constants (docs/tracer.md section 3; chosen by the
/// measurements in docs/benchmarks.md).
/// The surface near an edge lies within this many times its corners' largest
/// edge-point displacement of the chord: the edge points themselves, then the
/// rest of a geometric series with ratio <= 1/2 (the shells' own bound).
constexpr double k_series_factor = 2.0;
/// Pixels of deviation allowed per unit of tolerance. One sample per pixel
/// shows a silhouette off by a small fraction of a pixel (a pixel whose
/// centre it passes flips between surface and background), so at tolerance 1
/// the rule asks 1/80 px, which renders the blob5k views as close to the
/// reference as the size rule at tolerance 1 does.
constexpr double k_deviation_px = 1.0 / 80.0;
/// Shading: an edge wider than k_shading_min_px pixels refines while the
/// surface turns along it by more than k_max_turn radians times the tolerance
/// (an arc of chord h and sagitta s turns by about 8 s / h).
constexpr double k_shading_min_px = 2.0;
constexpr double k_max_turn = 0.025;

/// What a node's visit passes to its children's.
struct FromParent {
    double thickness = 0.0;   ///< the parent's slab thickness
    double snap_depth = 0.0;  ///< with snapped corners: the depth of the shell that holds them
};

/// One ray's walk through the hierarchy.
struct Walk {
    Walk(const SurfaceImpl& surface, const WalkSetup& w)
        : s(surface),
          view(*w.view),
          origin(w.origin),
          origin_distance(w.origin_distance),
          dir_length(glm::length(w.direction)),
          t_min(w.t_min),
          t_max(w.t_max),
          mode(w.mode),
          query(make_ray_box_query(w.origin, w.direction, w.t_min, w.t_max)),
          wray(detail::make_watertight_ray(w.origin, w.direction)),
          all_hits(w.all_hits),
          drawn_out(w.drawn_out) {}

    const SurfaceImpl& s;
    const View& view;
    Vec3 origin;
    double origin_distance;
    double dir_length;
    double t_min;
    double t_max;  ///< shrinks to the nearest hit in nearest mode (and query.t_max with it)
    WalkMode mode;
    RayBoxQuery query;
    detail::WatertightRay wray;
    std::vector<Hit>* all_hits;
    std::vector<std::array<Vec3, 3>>* drawn_out;
    Hit best;
    bool found = false;
    TraceCounters counters;
    /// All-hits mode: what each hit met, parallel to *all_hits.
    std::vector<detail::CrossingPart> parts;

    /// One pixel's width at distance d along the light path from the ray's
    /// origin (DESIGN section 5: angle * (D + d); orthographic: the pixel size).
    double pixel_width(double d) const {
        return view.orthographic ? view.pixel_size : view.pixel_angle * (origin_distance + d);
    }

    /// One pixel's width where the ray would meet edge (a, b): at its nearest
    /// point to the origin, bounded below by the distance to its midpoint
    /// minus half its length. Symmetric in a and b, so both sides agree.
    double pixel_width_at_edge(const Vec3& a, const Vec3& b, double length) const {
        if (view.orthographic) return view.pixel_size;
        const double to_mid = glm::length((a + b) * 0.5 - origin);
        return pixel_width(std::max(0.0, to_mid - 0.5 * length));
    }

    /// Whether edge e of a node refines, from data both of its triangles hold
    /// bit for bit: its level-L endpoints and their displacement (NodeRecord).
    bool edge_refines(const NodeRecord& rec, int e) const {
        const int f = (e + 1) % 3;
        const Vec3& a = rec.position[e];
        const Vec3& b = rec.position[f];
        const double length = glm::length(b - a);
        const double pixel = pixel_width_at_edge(a, b, length);
        const double tolerance = s.options.tolerance;
        if (s.options.refine == RefineRule::size) return length > pixel * tolerance;
        // Error: the surface may lie farther than tolerance pixels from the
        // chord drawn there (the same for every ray direction, so a secondary
        // ray from a hit sees the surface its camera ray saw, within a level).
        const double displacement = std::max(rec.displacement[e], rec.displacement[f]);
        if (k_series_factor * displacement > k_deviation_px * tolerance * pixel) return true;
        // Shading: the surface turns visibly along an edge wider than a few pixels.
        return length > k_shading_min_px * pixel &&
               8.0 * displacement > k_max_turn * tolerance * length;
    }

    /// Whether the ray enters the shell (every node does, collecting drawn triangles).
    bool enters(const Shell& shell, double& t_entry) const {
        if (mode == WalkMode::drawn) {
            t_entry = 0.0;
            return true;
        }
        // query.t_max is t_max (leaf() lowers both).
        return ray_hits_shell(query, shell, s.options.shell_kind, t_entry);
    }

    /// What a node's visit knows of a child: what it keeps of the node's
    /// corners (its drawn corners are filled only if the ray enters it: most
    /// children it misses), its edges, and whether and where the ray enters it.
    struct Child {
        NodeId id;
        std::int8_t kept[3];  ///< per corner: the node's corner it keeps (not alive), or -1: its own
        bool exists[3];
        double t_entry;
        bool hit;
    };

    /// Whether the ray enters each of a node's four children's shells, and
    /// where (their hit and t_entry).
    void children_entered(const std::array<Shell, 4>& shells, const DrawnCorner* parent, Child* children) const {
        if (mode == WalkMode::drawn) {
            for (int c = 0; c < 4; ++c) {
                children[c].hit = true;
                children[c].t_entry = 0.0;
            }
            return;
        }
        // Snapped corners can lie outside the node's own shell: grown by them
        // (in room left uninitialised, as child_shells' is in visit()).
        union GrownShells {
            GrownShells() {}
            std::array<Shell, 4> shells;
        } grown;
        const Shell* tested[4];
        for (int c = 0; c < 4; ++c) {
            const std::int8_t* kept = children[c].kept;
            tested[c] = &shells[c];
            if (kept[0] < 0 && kept[1] < 0 && kept[2] < 0) continue;
            grown.shells[c] = shells[c];
            for (int k = 0; k < 3; ++k)
                if (kept[k] >= 0) grown.shells[c].grow_both(parent[kept[k]].position);
            tested[c] = &grown.shells[c];
        }
        const ShellKind kind = s.options.shell_kind;
        for (int c = 0; c < 4; c += 2)
            detail::ray_hits_shell_pair(query, *tested[c], *tested[c + 1], kind, children[c].hit,
                                        children[c + 1].hit, children[c].t_entry, children[c + 1].t_entry);
    }

    void leaf(const NodeId& id, const NodeRecord& rec, const DrawnCorner* drawn,
              const FromParent& from_parent, bool capped) {
        ++counters.leaves_tested;
        if (mode == WalkMode::drawn) {
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
        h.normal = shading_normal(id, drawn, th);
        if (h.normal == Vec3(0.0)) h.normal = h.geometric_normal;
        const auto domain = [&](int c) { return grid_domain(drawn[c].normal_node, drawn[c].normal_corner); };
        const Vec2 w = th.b0 * domain(0) + th.b1 * domain(1) + th.b2 * domain(2);
        if (s.mesh.has_uvs()) {
            const Vec2* uv = &s.mesh.corner_uvs[3 * std::size_t{id.face}];
            h.uv = (1.0 - w.x - w.y) * uv[0] + w.x * uv[1] + w.y * uv[2];
        } else {
            h.uv = w;
        }
        h.base_barycentric = w;
        h.triangle = {drawn[0].position, drawn[1].position, drawn[2].position};
        h.level = id.level;
        h.base_face = id.face;
        h.capped_by_max_level = capped;
        // The leaf's shell holds every descendant to max_level; grown by the
        // corners it draws it holds the drawn point too, so its depth bounds
        // how far the two lie apart. A leaf with snapped corners draws part
        // of an ancestor's region: the ancestor's grown shell bounds that.
        Shell grown = rec.shell;
        for (int c = 0; c < 3; ++c) grown.grow_both(drawn[c].position);
        const Vec3 ap = glm::abs(h.point);
        const double rounding = gamma_bound(7) * (ap.x + ap.y + ap.z);
        h.surface_error = rounding + std::max(shell_depth(grown), from_parent.snap_depth);
        h.surface_error_px = h.surface_error / pixel_width(h.t * dir_length);
        // For secondary rays: a ray that stops one level coarser (a shadow ray
        // judges edges by their distance from this point, not from the
        // camera) sees the parent, inside the parent's shell.
        h.error_bound = rounding + std::max({0.0, shell_depth(grown), from_parent.thickness,
                                             from_parent.snap_depth});
        if (mode == WalkMode::all_hits) {
            parts.push_back(detail::crossing_part(wray, h.triangle, th, all_hits->size()));
            all_hits->push_back(h);
        } else {
            best = h;
            found = true;
            t_max = h.t;
            query.t_max = h.t;
        }
    }

    /// The leaf's smooth normal at the hit. Where its corners are its own and
    /// it has midpoint normals, the quadratic through the six (corners, edge
    /// midpoints one level down): a coarse leaf then shades about as a leaf
    /// one level finer would. Otherwise (snapped corners: the drawn triangle
    /// is not the node's; the user's normals) the corners' linear blend.
    /// The normals are read here, from the leaf's whole record and those its
    /// snapped corners came from.
    Vec3 shading_normal(const NodeId& id, const DrawnCorner* drawn, const detail::TriangleHit& th) const {
        const NodeRecord rec = s.hierarchy.node(id);
        Vec3 normal[3];
        for (int c = 0; c < 3; ++c) {
            const DrawnCorner& corner = drawn[c];
            normal[c] = corner.normal_node == id
                            ? rec.shading_normal[corner.normal_corner]
                            : s.hierarchy.node(corner.normal_node).shading_normal[corner.normal_corner];
        }
        const double b[3] = {th.b0, th.b1, th.b2};
        bool quadratic = !rec.linear_shading;
        for (int c = 0; c < 3; ++c)
            quadratic = quadratic && drawn[c].alive && rec.edge_normal[c] != glm::vec3(0.0f);
        Vec3 sum(0.0);
        for (int c = 0; c < 3; ++c) {
            if (!quadratic) {
                sum += b[c] * normal[c];
                continue;
            }
            // Quadratic Lagrange weights: b(2b - 1) at a corner, 4 b b' at a midpoint.
            const int d = (c + 1) % 3;
            sum += b[c] * (2.0 * b[c] - 1.0) * normal[c] + 4.0 * b[c] * b[d] * Vec3(rec.edge_normal[c]);
        }
        return finish_normal(sum);
    }

    /// How deep a shell is across the surface: its slab, or without one its box's diagonal.
    static double shell_depth(const Shell& shell) {
        if (shell.axis != Vec3(0.0)) return shell.thickness();
        return glm::length(shell.hi - shell.lo);
    }

    /// Starts the descent at the base triangles of a BVH leaf, their shells
    /// tested two at a time: the shells first, alone (a ray misses most of
    /// the base triangles it meets, five a ray in the close-up, so reading
    /// their whole records cost more than testing).
    void visit_roots(const std::uint32_t* faces, std::uint32_t count) {
        for (std::uint32_t k = 0; k < count; k += 2) {
            if (k + 1 == count || mode == WalkMode::drawn) {
                for (; k < count; ++k) {
                    const Shell shell = s.hierarchy.root_shell(faces[k]);
                    double t_entry;
                    if (enters(shell, t_entry)) visit_root(faces[k], shell);
                }
                return;
            }
            const Shell first = s.hierarchy.root_shell(faces[k]);
            const Shell second = s.hierarchy.root_shell(faces[k + 1]);
            bool hit_first = false, hit_second = false;
            double t_first = 0.0, t_second = 0.0;
            detail::ray_hits_shell_pair(query, first, second, s.options.shell_kind, hit_first, hit_second, t_first,
                                        t_second);
            if (hit_first) visit_root(faces[k], first);
            // Tested before the first's visit could lower t_max: the test
            // with the lower t_max fails exactly where the entry lies beyond it.
            if (hit_second && t_second <= query.t_max) visit_root(faces[k + 1], second);
        }
    }

    /// Descends from a base triangle whose shell the ray enters: its corners
    /// and edges are its own.
    void visit_root(std::uint32_t face, const Shell& shell) {
        const NodeId id = Hierarchy::root(face);
        NodeRecord rec = s.hierarchy.node(id, Hierarchy::Part::corners);
        rec.shell = shell;
        DrawnCorner drawn[3];
        for (int c = 0; c < 3; ++c) drawn[c] = {rec.draw_position[c], id, c, true};
        const bool exists[3] = {true, true, true};
        visit(id, rec, drawn, exists, FromParent{});
    }

    void visit(const NodeId& id, const NodeRecord& rec, const DrawnCorner* drawn,
               const bool* edge_exists, const FromParent& from_parent) {
        ++counters.nodes_visited;
        counters.deepest_level = std::max(counters.deepest_level, int{id.level});
        const bool naive = s.options.crack_rule == CrackRule::per_triangle;
        const bool at_max_level = id.level >= s.options.max_level;
        bool refine[3];
        bool any = false;
        for (int e = 0; e < 3; ++e) {
            refine[e] = edge_exists[e] && edge_refines(rec, e);
            any = any || refine[e];
        }
        const bool capped = at_max_level && any;
        if (at_max_level) refine[0] = refine[1] = refine[2] = any = false;
        // The paper's rule: the triangle alone decides and every child vertex
        // is its own (T-junctions wherever neighbours disagree).
        if (naive) refine[0] = refine[1] = refine[2] = any;
        if (!any) {
            leaf(id, rec, drawn, from_parent, capped);
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
        // What the children inherit: this node's slab, and where one of
        // them draws a snapped corner, how deep this node's grown shell is
        // (found for the first such child the ray enters: most visits have none).
        FromParent inherited;
        inherited.thickness = rec.shell.thickness();
        double snap_depth = -1.0;
        const auto depth_with_snapped = [&] {
            if (snap_depth < 0.0) {
                Shell grown = rec.shell;
                for (int c = 0; c < 3; ++c) grown.grow_both(drawn[c].position);
                snap_depth = std::max(from_parent.snap_depth, shell_depth(grown));
            }
            return snap_depth;
        };
        Child children[4];
        // Filled whole by child_shells, so left uninitialised: four Shells'
        // defaults copied in at every visit were 0.6% of a close-up's
        // instructions.
        union FreshShells {
            FreshShells() {}
            std::array<Shell, 4> shells;
        } fresh;
        std::array<Shell, 4>& child_shells = fresh.shells;
        s.hierarchy.child_shells(id, child_shells);
        for (int c = 0; c < 4; ++c) {
            Child& ch = children[c];
            ch.id = child_of(id, c);
            const auto& map = child_corners(id.down, c);
            for (int k = 0; k < 3; ++k) {
                const ChildCorner cc = map[k];
                const bool own =
                    naive || (cc.is_edge ? refine[cc.index] : drawn[cc.index].alive);
                // Not its own: a corner of this node's that is not alive
                // either, or the end of a frozen edge its midpoint snaps to.
                ch.kept[k] = static_cast<std::int8_t>(own ? -1 : cc.is_edge ? snap_to[cc.index] : cc.index);
            }
            for (int k = 0; k < 3; ++k) {
                const ChildCorner p = map[k], q = map[(k + 1) % 3];
                // Halves of a parent edge exist only if that edge refined.
                if (naive) ch.exists[k] = true;
                else if (!p.is_edge) ch.exists[k] = refine[q.index];
                else if (!q.is_edge) ch.exists[k] = refine[p.index];
                else ch.exists[k] = true;
            }
        }
        children_entered(child_shells, drawn, children);
        // The children the ray enters, nearest first: an insertion sort,
        // stable (children entered at the same distance keep their order).
        int order[4];
        double entry[4];
        int entered = 0;
        for (int c = 0; c < 4; ++c) {
            if (!children[c].hit) continue;
            const double t = children[c].t_entry;
            int k = entered++;
            for (; k > 0 && t < entry[k - 1]; --k) {
                order[k] = order[k - 1];
                entry[k] = entry[k - 1];
            }
            order[k] = c;
            entry[k] = t;
        }
        for (int k = 0; k < entered; ++k) {
            const int c_entered = order[k];
            Child& ch = children[c_entered];
            if (mode == WalkMode::nearest && ch.t_entry > t_max) break;
            const bool snapped = ch.kept[0] >= 0 || ch.kept[1] >= 0 || ch.kept[2] >= 0;
            inherited.snap_depth = snapped ? depth_with_snapped() : 0.0;
            // Its own corners come from its record, the others are this
            // node's (dead, where they were alive here: snapped); its shell
            // is the one tested above (the same bits), not decoded again.
            NodeRecord child_rec = s.hierarchy.node(ch.id, Hierarchy::Part::corners);
            child_rec.shell = child_shells[c_entered];
            DrawnCorner child_drawn[3];
            for (int c = 0; c < 3; ++c) {
                if (ch.kept[c] < 0) {
                    child_drawn[c] = {child_rec.draw_position[c], ch.id, c, true};
                } else {
                    child_drawn[c] = drawn[ch.kept[c]];
                    child_drawn[c].alive = false;
                }
            }
            visit(ch.id, child_rec, child_drawn, ch.exists, inherited);
        }
    }
};

}  // namespace

void SurfaceImpl::trace(const Ray& ray, bool all, Hit* nearest, bool* found,
                        std::vector<Hit>* hits, TraceCounters* counters) const {
    const double dir_length = glm::length(ray.direction);
    if (!(dir_length > 0.0) || !std::isfinite(dir_length) || !std::isfinite(ray.origin.x) ||
        !std::isfinite(ray.origin.y) || !std::isfinite(ray.origin.z)) {
        if (found) *found = false;
        return;
    }
    WalkSetup setup;
    setup.view = ray.view ? ray.view : &options.view;
    setup.origin = ray.origin;
    setup.direction = ray.direction;
    setup.origin_distance = ray.origin_distance >= 0.0 ? ray.origin_distance
                                                       : glm::length(ray.origin - setup.view->camera);
    setup.t_min = ray.t_min;
    setup.t_max = ray.t_max;
    setup.mode = all ? WalkMode::all_hits : WalkMode::nearest;
    setup.all_hits = hits;
    Walk walk(*this, setup);
    walk.counters.rays = 1;
    top.traverse_leaves(walk.query, walk.t_max,
                        [&](const std::uint32_t* faces, std::uint32_t count) { walk.visit_roots(faces, count); });
    if (found) *found = walk.found;
    if (nearest && walk.found) *nearest = walk.best;
    Totals& totals_here = my_totals();
    const auto count_hit = [&](const Hit& h) {
        totals_here.level_histogram[h.level].fetch_add(1, std::memory_order_relaxed);
        ++walk.counters.hits;
        walk.counters.error_bound_px_sum += h.surface_error_px;
        walk.counters.error_bound_px_max = std::max(walk.counters.error_bound_px_max, h.surface_error_px);
        walk.counters.hits_at_max_level += h.capped_by_max_level ? 1 : 0;
    };
    if (walk.found) count_hit(walk.best);
    if (all && hits) {
        detail::merge_crossings(walk.parts, *hits);
        for (const Hit& h : *hits) count_hit(h);
    }
    if (counters) counters->add(walk.counters);
    totals_here.add(walk.counters);
}

void SurfaceImpl::collect_drawn(const Vec3& origin, double origin_distance,
                                std::vector<std::array<Vec3, 3>>& out) const {
    WalkSetup setup;
    setup.view = &options.view;
    setup.origin = origin;
    setup.origin_distance = origin_distance;
    setup.mode = WalkMode::drawn;
    setup.drawn_out = &out;
    Walk walk(*this, setup);
    for (std::uint32_t face = 0; face < mesh.triangles.size(); ++face) walk.visit_roots(&face, 1);
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
    std::vector<std::uint64_t> histogram;
    s.trace = impl_->summed_totals(histogram);
    const HierarchyCounters h = impl_->hierarchy.counters();
    s.trace.cache_hits = h.node_hits;
    s.trace.cache_misses = h.node_misses;
    s.nodes_built = h.nodes_built;
    s.tiles_built = h.tiles_built;
    s.tile_build_seconds = h.tile_build_seconds;
    s.cache_evictions = h.evictions;
    s.cache_bytes = h.bytes;
    s.cache_peak_bytes = h.peak_bytes;
    s.shared_cache = impl_->hierarchy.cache()->stats();
    const Mesh& m = impl_->mesh;
    s.memory.mesh = m.positions.capacity() * sizeof(Vec3) + m.triangles.capacity() * sizeof(Triangle) +
                    m.corner_normals.capacity() * sizeof(Vec3) + m.corner_uvs.capacity() * sizeof(Vec2);
    s.memory.topology = h.topology_bytes;
    s.memory.bvh = impl_->top.memory_bytes();
    s.memory.roots = h.root_bytes;
    s.memory.fronts = h.front_bytes;
    s.memory.front_threads = h.fronts;
    s.memory.levels_below = h.below_bytes;
    s.base_triangles = m.triangles.size();
    s.leaf_level_histogram = std::move(histogram);
    while (!s.leaf_level_histogram.empty() && s.leaf_level_histogram.back() == 0)
        s.leaf_level_histogram.pop_back();
    return s;
}

std::uint64_t AdaptiveSurface::uniform_triangle_count(int level) const {
    return static_cast<std::uint64_t>(impl_->mesh.triangles.size()) << (2 * level);
}

}  // namespace subdivtrace

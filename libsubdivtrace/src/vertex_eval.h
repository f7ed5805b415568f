#pragma once
// Lazy evaluation of the uniform hierarchy's vertices: the position of a
// grid vertex at level L from the level L-1 vertices its stencil reads, the
// Gouraud normal at level L from its level-L ring. Results are memoised in a
// shared budgeted cache plus a per-call scratch table, so evaluation is
// bounded however small the cache is, and deterministic however full it is.

#include <vector>

#include "grid.h"
#include "lru_cache.h"
#include "ring_order.h"
#include "subdivtrace/scheme.h"

namespace subdivtrace::detail {

struct EvalKey {
    VertexKey vertex;
    std::uint8_t level = 0;
    std::uint8_t what = 0;  ///< 0 position, 1 normal, 2 drawn position, 3 displacement
    bool operator==(const EvalKey& o) const {
        return vertex == o.vertex && level == o.level && what == o.what;
    }
};

struct EvalKeyHash {
    std::size_t operator()(const EvalKey& k) const {
        return VertexKeyHash{}(k.vertex) ^ mix64((std::uint64_t{k.level} << 8) | k.what);
    }
};

/// A thread's private memo in front of the shared cache: open addressing
/// with linear probing in one flat array (node-based maps spent most of the
/// build time in cache misses). When half full it forgets everything, which
/// only costs recomputation: values are deterministic.
class EvalScratch {
public:
    explicit EvalScratch(unsigned log2_slots = 17) : slots_(std::size_t{1} << log2_slots) {}

    bool find(const EvalKey& key, Vec3& value) const {
        for (std::size_t i = slot_of(key);; i = (i + 1) & mask()) {
            const Slot& s = slots_[i];
            if (s.generation != generation_) return false;
            if (s.key == key) {
                value = s.value;
                return true;
            }
        }
    }

    void insert(const EvalKey& key, const Vec3& value) {
        if (2 * count_ >= slots_.size()) clear();
        for (std::size_t i = slot_of(key);; i = (i + 1) & mask()) {
            Slot& s = slots_[i];
            if (s.generation != generation_) {
                s = {key, value, generation_};
                ++count_;
                return;
            }
            if (s.key == key) return;
        }
    }

    /// Forgets every entry in O(1): slots of older generations count as empty.
    void clear() {
        count_ = 0;
        if (++generation_ == 0) {
            for (Slot& s : slots_) s.generation = 0;
            generation_ = 1;
        }
    }

private:
    struct Slot {
        EvalKey key;
        Vec3 value;
        std::uint32_t generation = 0;
    };
    std::size_t mask() const { return slots_.size() - 1; }
    std::size_t slot_of(const EvalKey& key) const { return EvalKeyHash{}(key) & mask(); }

    std::vector<Slot> slots_;
    std::uint32_t generation_ = 1;
    std::size_t count_ = 0;
};

/// A vertex's incident triangles at a level, as directed pairs (its ring).
using KeyPairs = std::vector<FanPair<VertexKey>>;

class VertexEvaluator {
public:
    VertexEvaluator(const BaseTopology& topo, SchemeKind scheme, std::size_t budget_bytes);

    Vec3 position(const VertexKey& v, int level, EvalScratch& scratch);
    Vec3 normal(const VertexKey& v, int level, EvalScratch& scratch);
    /// Where the tracer draws v: its position (interpolating schemes) or its
    /// Loop limit point, computed at its birth level so it is one value for
    /// every leaf that draws it.
    Vec3 draw_position(const VertexKey& v, EvalScratch& scratch);

    /// Largest distance of a level-(level+1) edge point from its edge's
    /// midpoint, over the edges from v at `level` (the local displacement that
    /// bounds an interpolating scheme's descendants, section 4 of DESIGN.md).
    double edge_displacement(const VertexKey& v, int level, EvalScratch& scratch);

    /// Incident triangles of v at `level`, as pairs (from, to) of its ring.
    void incident_pairs(const VertexKey& v, int level, KeyPairs& out) const;

    const BaseTopology& topology() const { return topo_; }
    CacheCounters counters() const { return cache_.counters(); }

private:
    Vec3 compute(const EvalKey& key, EvalScratch& scratch);
    Vec3 compute_position(const VertexKey& v, int level, EvalScratch& scratch);
    Vec3 compute_normal(const VertexKey& v, int level, EvalScratch& scratch);
    Vec3 compute_draw_position(const VertexKey& v, EvalScratch& scratch);
    Vec3 compute_edge_displacement(const VertexKey& v, int level, EvalScratch& scratch);
    Vec3 edge_rule(const VertexKey& a, const VertexKey& b, int level, EvalScratch& scratch);
    void fill_ring(const VertexKey& v, int level, VertexRing& ring,
                   OrderedRing<VertexKey>& ordered, EvalScratch& scratch);
    Vec3 lookup(const EvalKey& key, EvalScratch& scratch);

    const BaseTopology& topo_;
    SchemeKind scheme_;
    ShardedLruCache<EvalKey, Vec3, EvalKeyHash> cache_;
};

}  // namespace subdivtrace::detail

#pragma once
/// \file tile_cache.h
/// One tile cache for a whole scene: every AdaptiveSurface (and every
/// Hierarchy) given the same TileCache shares its byte budget, and tiles are
/// dropped by recency across all of them (DESIGN.md section 5, "Memory").
/// A budget per object multiplies with the object count; one per scene does
/// not. Embree keeps one tessellation cache per device for the same reason.
///
/// Thread-safe: any number of threads may trace any number of surfaces that
/// share one cache. A tile is built by one thread only: others asking for it
/// meanwhile wait for that build (lookup_or_build, Embree's per-entry state)
/// instead of building it again. What a ray sees never depends on the cache's
/// contents: an evicted tile is rebuilt bit-identically when asked again.

#include <cstddef>
#include <cstdint>
#include <memory>

namespace subdivtrace {

namespace detail {
class TileCacheImpl;
}

/// What a TileCache did, over every surface that uses it.
struct TileCacheStats {
    std::size_t budget_bytes = 0;  ///< the budget now: a ceiling
    /// What the cache keeps now: it starts at 8 MB (or the budget, if
    /// lower) and grows, up to the budget, while tiles it dropped are asked
    /// for again (remisses).
    std::size_t limit_bytes = 0;
    std::size_t bytes = 0;         ///< what its tiles are charged now
    /// The most its tiles were charged at once (exact: one running total
    /// over all shards). Each shard keeps budget / shards, so this stays at
    /// or below the budget, but for the few tiles every shard keeps.
    std::size_t peak_bytes = 0;
    std::uint64_t hits = 0;       ///< lookups that found the tile ready
    std::uint64_t misses = 0;     ///< lookups that built the tile
    /// Tiles built and cached: the misses' tiles, and the tiles of a base
    /// triangle's chunk built with it (docs/tracer.md).
    std::uint64_t insertions = 0;
    /// Lookups that found the tile being built by another thread and waited
    /// for it (each would have been a duplicate build without the wait).
    std::uint64_t waits = 0;
    /// Tiles built while the same tile was already cached or being built: the
    /// work lookup_or_build exists to avoid. Stays 0; counted to prove it.
    std::uint64_t duplicate_builds = 0;
    std::uint64_t evictions = 0;  ///< tiles dropped to keep within the limit
    /// Misses on tiles dropped recently (the cache remembers four dropped
    /// tiles for each it holds): each would have been a hit in a larger
    /// cache, and each grows the limit.
    std::uint64_t remisses = 0;
    std::size_t surfaces = 0;     ///< hierarchies alive that use this cache
};

/// A byte-budgeted cache of subdivision tiles, shared by any number of
/// surfaces. The budget is a ceiling: a picture whose tiles fit in less
/// (most do) keeps less (TileCacheStats::limit_bytes). Pass one in
/// SurfaceOptions::cache to every surface of a scene; keep it (a
/// shared_ptr) as long as any of them. Its entries are keyed by
/// the surface (an id never reused) and the tile, so surfaces never see each
/// other's tiles; a surface's tiles leave the cache when it is destroyed.
class TileCache {
public:
    /// Default scene budget in MB (docs/povray.md, "Choosing the budget", measures the choice).
    static constexpr std::size_t k_default_mb = 128;

    /// How much of the budget the cache keeps.
    enum class Sizing {
        on_demand,     ///< a working limit that grows while dropped tiles come back
        whole_budget,  ///< the whole budget from the start (fixed)
    };

    /// A cache charging at most about `budget_bytes` (see peak_bytes), and
    /// with Sizing::on_demand only what its pictures need below that
    /// (limit_bytes). A tiny budget is legal: it only costs rebuilding tiles.
    explicit TileCache(std::size_t budget_bytes = k_default_mb << 20, Sizing sizing = Sizing::on_demand);
    ~TileCache();
    TileCache(const TileCache&) = delete;
    TileCache& operator=(const TileCache&) = delete;

    /// Changes the budget; thread-safe. A smaller budget (and the working
    /// limit, lowered to it) evicts at the next insertion into each part of
    /// the cache, not at once; a larger one lets the limit grow further.
    void set_budget(std::size_t budget_bytes);
    std::size_t budget() const;

    TileCacheStats stats() const;

    /// The implementation (library internal: hierarchy.cpp).
    detail::TileCacheImpl& impl() const { return *impl_; }

private:
    std::unique_ptr<detail::TileCacheImpl> impl_;
};

}  // namespace subdivtrace

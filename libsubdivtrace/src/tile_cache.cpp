#include "subdivtrace/tile_cache.h"

#include "tile_cache_impl.h"

namespace subdivtrace {

TileCache::TileCache(std::size_t budget_bytes, Sizing sizing)
    : impl_(std::make_unique<detail::TileCacheImpl>(budget_bytes, sizing == Sizing::whole_budget)) {}

TileCache::~TileCache() = default;

void TileCache::set_budget(std::size_t budget_bytes) { impl_->set_budget(budget_bytes); }

std::size_t TileCache::budget() const { return impl_->budget(); }

TileCacheStats TileCache::stats() const {
    const detail::CacheCounters c = impl_->counters();
    TileCacheStats s;
    s.budget_bytes = impl_->budget();
    s.bytes = c.bytes;
    s.peak_bytes = c.peak_bytes;
    s.hits = c.hits;
    s.misses = c.misses;
    s.waits = c.waits;
    s.insertions = c.insertions;
    s.duplicate_builds = c.duplicate_builds;
    s.evictions = c.evictions;
    s.limit_bytes = c.limit;
    s.remisses = c.remisses;
    s.surfaces = impl_->surfaces.load(std::memory_order_relaxed);
    return s;
}

}  // namespace subdivtrace

#pragma once
// The inside of subdivtrace::TileCache: a ShardedLruCache of tiles keyed by
// (surface id, tile root), shared by every hierarchy given the same cache.

#include <atomic>
#include <cstdint>
#include <memory>

#include "lru_cache.h"
#include "node_address.h"
#include "subdivtrace/tile_cache.h"

namespace subdivtrace::detail {

struct CachedTile;  // hierarchy.cpp

/// A tile of one surface: ids are never reused, so a key never names a
/// destroyed surface's tile as a new one's.
struct TileKey {
    std::uint64_t surface = 0;
    NodeId root;
    bool operator==(const TileKey& o) const { return surface == o.surface && root == o.root; }
};

struct TileKeyHash {
    std::size_t operator()(const TileKey& k) const {
        const NodeId& n = k.root;
        const std::uint64_t h0 = (std::uint64_t{n.face} << 32) | (std::uint64_t{n.level} << 1) | n.down;
        const std::uint64_t h1 = (std::uint64_t{n.i} << 32) | n.j;
        return static_cast<std::size_t>(mix64(h0 ^ mix64(h1 ^ mix64(k.surface))));
    }
};

class TileCacheImpl
    : public ShardedLruCache<TileKey, std::shared_ptr<const CachedTile>, TileKeyHash> {
public:
    using ShardedLruCache::ShardedLruCache;
    std::atomic<std::size_t> surfaces{0};  ///< hierarchies alive that use it
};

}  // namespace subdivtrace::detail

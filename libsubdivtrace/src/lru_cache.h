#pragma once
// A thread-safe cache with a byte budget: sharded hash maps, each shard with
// its own mutex and least-recently-used list (the shape of Embree's
// tessellation cache: lookup(key) or insert(key, value), values copied out so a
// reader never holds a pointer an eviction could free).

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <list>
#include <mutex>
#include <unordered_map>
#include <utility>
#include <vector>

namespace subdivtrace::detail {

struct CacheCounters {
    std::uint64_t hits = 0;
    std::uint64_t misses = 0;
    std::uint64_t insertions = 0;
    std::uint64_t evictions = 0;
    std::size_t bytes = 0;
    std::size_t peak_bytes = 0;
};

template <class Key, class Value, class Hash>
class ShardedLruCache {
public:
    /// Cost of one entry's bookkeeping as allocated: the key twice (list and
    /// map), the value, its byte count, two list pointers, the map node's next
    /// pointer, cached hash and iterator, a bucket slot, and malloc's header on
    /// both nodes. What the value owns besides is passed to insert().
    static constexpr std::size_t k_entry_bytes = 2 * sizeof(Key) + sizeof(Value) + 88;

    explicit ShardedLruCache(std::size_t budget_bytes, std::size_t shard_count = 64)
        : shards_(shard_count) {
        set_budget(budget_bytes);
    }

    void set_budget(std::size_t budget_bytes) {
        // Every shard keeps at least a few entries, so a tiny budget still
        // makes progress (it only costs recomputation).
        budget_per_shard_ = budget_bytes / shards_.size();
    }

    /// Copies the cached value into `out`; false on a miss.
    bool lookup(const Key& key, Value& out) {
        Shard& s = shard_for(key);
        std::lock_guard<std::mutex> lock(s.mutex);
        auto it = s.map.find(key);
        if (it == s.map.end()) {
            ++s.misses;
            return false;
        }
        ++s.hits;
        s.order.splice(s.order.begin(), s.order, it->second);
        out = it->second->value;
        return true;
    }

    /// Inserts (or keeps the existing value for) key, evicting the least
    /// recently used entries of the shard past the budget. `owned_bytes` is
    /// what the value owns beyond its own size (heap arrays).
    void insert(const Key& key, const Value& value, std::size_t owned_bytes = 0) {
        Shard& s = shard_for(key);
        std::lock_guard<std::mutex> lock(s.mutex);
        if (s.map.count(key)) return;
        const std::size_t cost = k_entry_bytes + owned_bytes;
        s.order.push_front({key, value, cost});
        s.map.emplace(key, s.order.begin());
        s.bytes += cost;
        ++s.insertions;
        // Every shard keeps a few entries, so a tiny budget still makes
        // progress (it only costs recomputation).
        while (s.bytes > budget_per_shard_ && s.map.size() > k_min_entries) {
            s.bytes -= s.order.back().bytes;
            s.map.erase(s.order.back().key);
            s.order.pop_back();
            ++s.evictions;
        }
        s.peak_bytes = std::max(s.peak_bytes, s.bytes);
    }

    CacheCounters counters() const {
        CacheCounters c;
        for (const Shard& s : shards_) {
            std::lock_guard<std::mutex> lock(s.mutex);
            c.hits += s.hits;
            c.misses += s.misses;
            c.insertions += s.insertions;
            c.evictions += s.evictions;
            c.bytes += s.bytes;
            c.peak_bytes += s.peak_bytes;
        }
        return c;
    }

private:
    struct Entry {
        Key key;
        Value value;
        std::size_t bytes;
    };
    struct Shard {
        mutable std::mutex mutex;
        std::list<Entry> order;
        std::unordered_map<Key, typename std::list<Entry>::iterator, Hash> map;
        std::uint64_t hits = 0, misses = 0, insertions = 0, evictions = 0;
        std::size_t bytes = 0, peak_bytes = 0;
    };
    static constexpr std::size_t k_min_entries = 2;

    Shard& shard_for(const Key& key) {
        // The high bits of the hash pick the shard, the map uses all of them.
        const std::size_t h = Hash{}(key);
        return shards_[(h >> 7) % shards_.size()];
    }

    std::vector<Shard> shards_;
    std::size_t budget_per_shard_ = 0;
};

}  // namespace subdivtrace::detail

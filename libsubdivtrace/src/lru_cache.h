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
    /// Cost of one entry as allocated: the key twice (list and map), the
    /// value, two list pointers, the map node's next pointer, cached hash and
    /// iterator, a bucket slot, and malloc's header on both nodes.
    static constexpr std::size_t k_entry_bytes = 2 * sizeof(Key) + sizeof(Value) + 80;

    explicit ShardedLruCache(std::size_t budget_bytes, std::size_t shard_count = 64)
        : shards_(shard_count) {
        set_budget(budget_bytes);
    }

    void set_budget(std::size_t budget_bytes) {
        // Every shard keeps at least a few entries, so a tiny budget still
        // makes progress (it only costs recomputation).
        const std::size_t per_shard = budget_bytes / shards_.size();
        max_entries_per_shard_ = std::max<std::size_t>(4, per_shard / k_entry_bytes);
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
        out = it->second->second;
        return true;
    }

    /// Inserts (or keeps the existing value for) key, evicting the least
    /// recently used entries of the shard past the budget.
    void insert(const Key& key, const Value& value) {
        Shard& s = shard_for(key);
        std::lock_guard<std::mutex> lock(s.mutex);
        if (s.map.count(key)) return;
        s.order.emplace_front(key, value);
        s.map.emplace(key, s.order.begin());
        ++s.insertions;
        while (s.map.size() > max_entries_per_shard_) {
            s.map.erase(s.order.back().first);
            s.order.pop_back();
            ++s.evictions;
        }
        s.peak_entries = std::max(s.peak_entries, s.map.size());
    }

    CacheCounters counters() const {
        CacheCounters c;
        for (const Shard& s : shards_) {
            std::lock_guard<std::mutex> lock(s.mutex);
            c.hits += s.hits;
            c.misses += s.misses;
            c.insertions += s.insertions;
            c.evictions += s.evictions;
            c.bytes += s.map.size() * k_entry_bytes;
            c.peak_bytes += s.peak_entries * k_entry_bytes;
        }
        return c;
    }

private:
    struct Shard {
        mutable std::mutex mutex;
        std::list<std::pair<Key, Value>> order;
        std::unordered_map<Key, typename std::list<std::pair<Key, Value>>::iterator, Hash> map;
        std::uint64_t hits = 0, misses = 0, insertions = 0, evictions = 0;
        std::size_t peak_entries = 0;
    };

    Shard& shard_for(const Key& key) {
        // The high bits of the hash pick the shard, the map uses all of them.
        const std::size_t h = Hash{}(key);
        return shards_[(h >> 7) % shards_.size()];
    }

    std::vector<Shard> shards_;
    std::size_t max_entries_per_shard_ = 4;
};

}  // namespace subdivtrace::detail

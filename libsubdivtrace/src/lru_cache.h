#pragma once
// A thread-safe cache with a byte budget, shared by all render threads: the
// shape of Embree's tessellation cache (lookup(key) or insert(key, value),
// values copied out, so a reader never holds memory an eviction could free).
//
// Sharded: each shard is one flat open-addressing table (linear probing,
// at most 3/4 full) under its own mutex, with CLOCK eviction (a referenced
// bit per entry, a hand that sweeps), which approximates least-recently-used
// without a list: about 2/3 of the memory of a node-based map plus list, and
// no allocation per entry.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <mutex>
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
    explicit ShardedLruCache(std::size_t budget_bytes, std::size_t shard_count = 64)
        : shards_(shard_count) {
        // The largest table per shard that fits the budget, kept at most 3/4
        // full (linear probing stays short at that load).
        const std::size_t slots = std::max<std::size_t>(8, budget_bytes / shards_.size() / sizeof(Slot));
        // Every shard keeps a few entries, so a tiny budget still makes
        // progress (it only costs recomputation).
        capacity_ = slots * 3 / 4;
        for (Shard& s : shards_) s.slots.resize(slots);
    }

    /// Copies the cached value into `out`; false on a miss.
    bool lookup(const Key& key, Value& out) {
        const std::size_t h = Hash{}(key);
        Shard& s = shard_for(h);
        std::lock_guard<std::mutex> lock(s.mutex);
        const std::size_t n = s.slots.size();
        for (std::size_t i = home(h, n);; i = next(i, n)) {
            Slot& slot = s.slots[i];
            if (!slot.full) {
                ++s.misses;
                return false;
            }
            if (slot.key == key) {
                ++s.hits;
                slot.referenced = true;
                out = slot.value;
                return true;
            }
        }
    }

    /// Inserts (or keeps the existing value for) key, evicting entries the
    /// clock hand finds unreferenced while the shard is at capacity.
    void insert(const Key& key, const Value& value) {
        const std::size_t h = Hash{}(key);
        Shard& s = shard_for(h);
        std::lock_guard<std::mutex> lock(s.mutex);
        const std::size_t n = s.slots.size();
        for (std::size_t i = home(h, n);; i = next(i, n)) {
            if (!s.slots[i].full) break;
            if (s.slots[i].key == key) return;
        }
        while (s.count >= capacity_) evict_one(s);
        for (std::size_t i = home(h, n);; i = next(i, n)) {
            Slot& slot = s.slots[i];
            if (!slot.full) {
                slot.key = key;
                slot.value = value;
                slot.full = true;
                slot.referenced = false;
                ++s.count;
                ++s.insertions;
                s.peak = std::max(s.peak, s.count);
                return;
            }
        }
    }

    CacheCounters counters() const {
        CacheCounters c;
        for (const Shard& s : shards_) {
            std::lock_guard<std::mutex> lock(s.mutex);
            c.hits += s.hits;
            c.misses += s.misses;
            c.insertions += s.insertions;
            c.evictions += s.evictions;
            // The tables are allocated whole: that is the memory they hold.
            c.bytes += s.slots.size() * sizeof(Slot);
            c.peak_bytes += s.slots.size() * sizeof(Slot);
        }
        return c;
    }

private:
    struct Slot {
        Key key{};
        Value value{};
        bool full = false;
        bool referenced = false;
    };
    struct Shard {
        mutable std::mutex mutex;
        std::vector<Slot> slots;
        std::size_t count = 0;
        std::size_t hand = 0;
        std::uint64_t hits = 0, misses = 0, insertions = 0, evictions = 0;
        std::size_t peak = 0;
    };

    static std::size_t home(std::size_t h, std::size_t n) { return (h ^ (h >> 29)) % n; }
    static std::size_t next(std::size_t i, std::size_t n) { return i + 1 == n ? 0 : i + 1; }

    Shard& shard_for(std::size_t h) { return shards_[(h >> 7) % shards_.size()]; }

    /// CLOCK: clear referenced bits until an unreferenced entry comes up,
    /// remove it, and close the gap (backward-shift deletion keeps linear
    /// probing correct without tombstones).
    void evict_one(Shard& s) {
        const std::size_t n = s.slots.size();
        for (;;) {
            Slot& slot = s.slots[s.hand];
            const std::size_t at = s.hand;
            s.hand = next(s.hand, n);
            if (!slot.full) continue;
            if (slot.referenced) {
                slot.referenced = false;
                continue;
            }
            erase_at(s, at);
            ++s.evictions;
            return;
        }
    }

    void erase_at(Shard& s, std::size_t i) {
        const std::size_t n = s.slots.size();
        s.slots[i].full = false;
        --s.count;
        for (std::size_t j = next(i, n); s.slots[j].full; j = next(j, n)) {
            const std::size_t k = home(Hash{}(s.slots[j].key), n);
            // Move j back into the gap unless its home lies cyclically in (i, j].
            const bool home_between = i <= j ? (i < k && k <= j) : (i < k || k <= j);
            if (home_between) continue;
            s.slots[i] = s.slots[j];
            s.slots[j].full = false;
            i = j;
        }
    }

    std::vector<Shard> shards_;
    std::size_t capacity_ = 4;
};

}  // namespace subdivtrace::detail

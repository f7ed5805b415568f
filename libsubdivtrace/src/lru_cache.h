#pragma once
// A thread-safe cache with a byte budget: sharded hash maps, each shard with
// its own mutex and least-recently-used list (the shape of Embree's
// tessellation cache). lookup_or_build(key, build) builds each value once:
// a thread asking for a key another thread is building waits for that build
// (a per-entry pending state) instead of building it again. Values are copied
// out, so a reader never holds a pointer an eviction could free. Each entry is
// charged to an owner (a surface sharing the cache) so owners can report their
// own share.

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <future>
#include <list>
#include <mutex>
#include <stdexcept>
#include <unordered_map>
#include <utility>
#include <vector>

namespace subdivtrace::detail {

/// Raises `a` to at least `v` (relaxed: a statistic, not a synchronisation).
inline void atomic_raise(std::atomic<std::size_t>& a, std::size_t v) {
    std::size_t cur = a.load(std::memory_order_relaxed);
    while (cur < v && !a.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {
    }
}

/// One owner's share of a cache: what its entries are charged and what
/// happened to them. Must outlive its entries (see erase_owner).
struct CacheOwnerTally {
    std::atomic<std::uint64_t> hits{0};    ///< found ready, or built by another thread meanwhile
    std::atomic<std::uint64_t> misses{0};  ///< built by the caller
    std::atomic<std::uint64_t> evictions{0};
    std::atomic<std::size_t> bytes{0};
    std::atomic<std::size_t> peak_bytes{0};
};

struct CacheCounters {
    std::uint64_t hits = 0;
    std::uint64_t misses = 0;
    std::uint64_t waits = 0;
    std::uint64_t duplicate_builds = 0;
    std::uint64_t insertions = 0;
    std::uint64_t evictions = 0;
    std::size_t bytes = 0;
    std::size_t peak_bytes = 0;
};

template <class Key, class Value, class Hash>
class ShardedLruCache {
public:
    /// Cost of one entry's bookkeeping as allocated: the key twice (list and
    /// map), the value, its byte count and owner, two list pointers, the map
    /// node's next pointer, cached hash and iterator, a bucket slot, and
    /// malloc's header on both nodes. What the value owns besides is passed
    /// by the build.
    static constexpr std::size_t k_entry_bytes =
        2 * sizeof(Key) + sizeof(Value) + sizeof(void*) + 88;
    static constexpr std::size_t k_shards = 64;

    explicit ShardedLruCache(std::size_t budget_bytes) : shards_(k_shards) {
        set_budget(budget_bytes);
    }

    void set_budget(std::size_t budget_bytes) {
        budget_.store(budget_bytes, std::memory_order_relaxed);
        budget_per_shard_.store(budget_bytes / shards_.size(), std::memory_order_relaxed);
    }
    std::size_t budget() const { return budget_.load(std::memory_order_relaxed); }

    /// The value cached under `key`, or `build()` (returning the value and
    /// the bytes it owns beyond sizeof(Value)) run by this thread while any
    /// other thread asking for the same key waits for it. `build` runs with
    /// no lock held, so it may look up other keys (a tile's parent); an
    /// exception it throws reaches every waiting thread and nothing is cached.
    template <class Build>
    Value lookup_or_build(const Key& key, CacheOwnerTally& owner, Build&& build) {
        return lookup_or_build_group(
            key, owner, [] { return std::vector<Key>(); },
            [&](const std::vector<Key>&) { return std::vector<std::pair<Value, std::size_t>>{build()}; });
    }

    /// As lookup_or_build, for a value best built together with others (a
    /// tile with its group's): on a miss, the keys of group() that are
    /// neither cached nor being built are claimed as well (a thread asking
    /// for one of them waits for this build), and build(claimed) returns a
    /// value and its bytes for each claimed key, in order; `key` is claimed[0].
    template <class Group, class Build>
    Value lookup_or_build_group(const Key& key, CacheOwnerTally& owner, Group&& group, Build&& build) {
        Shard& s = shard_for(key);
        std::shared_future<Value> other_build;
        std::vector<std::promise<Value>> promises;
        {
            std::lock_guard<std::mutex> lock(s.mutex);
            auto it = s.map.find(key);
            if (it != s.map.end()) {
                ++s.hits;
                owner.hits.fetch_add(1, std::memory_order_relaxed);
                s.order.splice(s.order.begin(), s.order, it->second);
                return it->second->value;
            }
            auto p = s.pending.find(key);
            if (p != s.pending.end()) {
                ++s.waits;
                owner.hits.fetch_add(1, std::memory_order_relaxed);
                other_build = p->second;
            } else {
                ++s.misses;
                owner.misses.fetch_add(1, std::memory_order_relaxed);
                // A promise allocates its shared state: made on a miss only.
                promises.emplace_back();
                s.pending.emplace(key, promises[0].get_future().share());
            }
        }
        if (other_build.valid()) return other_build.get();

        // This thread builds `key`, and the group's keys nobody has or builds.
        std::vector<Key> claimed{key};
        for (const Key& k : group()) {
            if (k == key) continue;
            Shard& g = shard_for(k);
            std::lock_guard<std::mutex> lock(g.mutex);
            if (g.map.count(k) != 0 || g.pending.count(k) != 0) continue;
            promises.emplace_back();
            g.pending.emplace(k, promises.back().get_future().share());
            claimed.push_back(k);
        }
        std::vector<std::pair<Value, std::size_t>> built;
        try {
            built = build(claimed);
            if (built.size() != claimed.size()) throw std::logic_error("cache: a group build returned a wrong count");
        } catch (...) {
            for (std::size_t k = 0; k < claimed.size(); ++k) {
                Shard& g = shard_for(claimed[k]);
                {
                    std::lock_guard<std::mutex> lock(g.mutex);
                    g.pending.erase(claimed[k]);
                }
                promises[k].set_exception(std::current_exception());
            }
            throw;
        }
        for (std::size_t k = 0; k < claimed.size(); ++k) {
            promises[k].set_value(built[k].first);
            Shard& g = shard_for(claimed[k]);
            std::lock_guard<std::mutex> lock(g.mutex);
            g.pending.erase(claimed[k]);
            insert_locked(g, claimed[k], built[k].first, built[k].second, owner);
        }
        return built[0].first;
    }

    /// Charges the entry under `key` `to` bytes instead of `from` (what its
    /// value owns grew or shrank), if it is cached and is(value) holds (not
    /// a rebuilt value under the same key); may evict to keep the budget.
    template <class Is>
    void recharge(const Key& key, Is is, std::size_t from, std::size_t to) {
        Shard& s = shard_for(key);
        std::lock_guard<std::mutex> lock(s.mutex);
        auto it = s.map.find(key);
        if (it == s.map.end() || !is(it->second->value)) return;
        Entry& e = *it->second;
        CacheOwnerTally& owner = *e.owner;  // the entry itself may be evicted below
        // Unsigned arithmetic wraps consistently: adding (to - from) is exact.
        e.bytes += to - from;
        s.bytes += to - from;
        total_bytes_.fetch_add(to - from, std::memory_order_relaxed);
        owner.bytes.fetch_add(to - from, std::memory_order_relaxed);
        evict_over_budget_locked(s);
        atomic_raise(peak_bytes_, total_bytes_.load(std::memory_order_relaxed));
        atomic_raise(owner.peak_bytes, owner.bytes.load(std::memory_order_relaxed));
    }

    /// Drops every entry charged to `owner` (not counted as evictions). No
    /// thread may be building an entry for it.
    void erase_owner(const CacheOwnerTally& owner) {
        for (Shard& s : shards_) {
            std::lock_guard<std::mutex> lock(s.mutex);
            for (auto it = s.order.begin(); it != s.order.end();) {
                if (it->owner != &owner) {
                    ++it;
                    continue;
                }
                s.bytes -= it->bytes;
                total_bytes_.fetch_sub(it->bytes, std::memory_order_relaxed);
                s.map.erase(it->key);
                it = s.order.erase(it);
            }
        }
    }

    CacheCounters counters() const {
        CacheCounters c;
        for (const Shard& s : shards_) {
            std::lock_guard<std::mutex> lock(s.mutex);
            c.hits += s.hits;
            c.misses += s.misses;
            c.waits += s.waits;
            c.duplicate_builds += s.duplicate_builds;
            c.insertions += s.insertions;
            c.evictions += s.evictions;
        }
        c.bytes = total_bytes_.load(std::memory_order_relaxed);
        c.peak_bytes = peak_bytes_.load(std::memory_order_relaxed);
        return c;
    }

private:
    struct Entry {
        Key key;
        Value value;
        std::size_t bytes;
        CacheOwnerTally* owner;
    };
    struct Shard {
        mutable std::mutex mutex;
        std::list<Entry> order;
        std::unordered_map<Key, typename std::list<Entry>::iterator, Hash> map;
        /// Keys being built, with the future their builder fulfils.
        std::unordered_map<Key, std::shared_future<Value>, Hash> pending;
        std::uint64_t hits = 0, misses = 0, waits = 0, duplicate_builds = 0, insertions = 0,
                      evictions = 0;
        std::size_t bytes = 0;
    };
    /// Every shard keeps a few entries, so a tiny budget still makes
    /// progress (it only costs recomputation).
    static constexpr std::size_t k_min_entries = 2;

    void insert_locked(Shard& s, const Key& key, const Value& value, std::size_t owned_bytes,
                       CacheOwnerTally& owner) {
        if (s.map.count(key)) {
            // Only a second build of the same key gets here; pending entries
            // make that impossible, so this counts what should never happen.
            ++s.duplicate_builds;
            return;
        }
        const std::size_t cost = k_entry_bytes + owned_bytes;
        s.order.push_front({key, value, cost, &owner});
        s.map.emplace(key, s.order.begin());
        s.bytes += cost;
        ++s.insertions;
        total_bytes_.fetch_add(cost, std::memory_order_relaxed);
        const std::size_t owner_bytes = owner.bytes.fetch_add(cost, std::memory_order_relaxed) + cost;
        evict_over_budget_locked(s);
        // Peaks after this insertion's evictions: what stays charged.
        atomic_raise(peak_bytes_, total_bytes_.load(std::memory_order_relaxed));
        atomic_raise(owner.peak_bytes, std::min(owner_bytes, owner.bytes.load(std::memory_order_relaxed)));
    }

    /// Drops the least recently used entries while the shard is over its budget.
    void evict_over_budget_locked(Shard& s) {
        const std::size_t shard_budget = budget_per_shard_.load(std::memory_order_relaxed);
        while (s.bytes > shard_budget && s.order.size() > k_min_entries) {
            Entry& victim = s.order.back();
            s.bytes -= victim.bytes;
            total_bytes_.fetch_sub(victim.bytes, std::memory_order_relaxed);
            victim.owner->bytes.fetch_sub(victim.bytes, std::memory_order_relaxed);
            victim.owner->evictions.fetch_add(1, std::memory_order_relaxed);
            s.map.erase(victim.key);
            s.order.pop_back();
            ++s.evictions;
        }
    }

    Shard& shard_for(const Key& key) {
        // The high bits of the hash pick the shard, the map uses all of them.
        const std::size_t h = Hash{}(key);
        return shards_[(h >> 7) % shards_.size()];
    }

    std::vector<Shard> shards_;
    std::atomic<std::size_t> budget_{0};
    std::atomic<std::size_t> budget_per_shard_{0};
    std::atomic<std::size_t> total_bytes_{0};
    std::atomic<std::size_t> peak_bytes_{0};
};

}  // namespace subdivtrace::detail

#pragma once
// A thread-safe cache with a byte budget: sharded hash maps, each shard with
// its own mutex and least-recently-used list (the shape of Embree's
// tessellation cache). lookup_or_build(key, build) builds each value once:
// a thread asking for a key another thread is building waits for that build
// (a pending state per build, shared by the keys it claimed) instead of
// building it again. Values are copied out, so a reader never holds a pointer
// an eviction could free. Each entry is charged to an owner (a surface sharing
// the cache) so owners can report their own share.
//
// The budget is a ceiling: the cache keeps at most a working limit, which
// starts small and grows while entries it dropped are asked for again (a
// "re-miss": the key is among the recently evicted ones it remembers, as
// ARC's ghost lists do). A picture whose working set fits the limit never
// grows it; one whose rays keep coming back to dropped tiles grows it until
// they stop, up to the budget (docs/tracer.md, "Cache and memory").

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <exception>
#include <condition_variable>
#include <memory>
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
    /// Misses on a key evicted recently (each would have hit in a larger
    /// cache): what grows the limit.
    std::uint64_t remisses = 0;
    std::size_t bytes = 0;
    std::size_t peak_bytes = 0;
    std::size_t limit = 0;  ///< the working limit now (at most the budget)
};

template <class Key, class Value, class Hash>
class ShardedLruCache {
    /// A cached value, linked from the most recently used to the least.
    struct Entry {
        Value value;
        std::size_t bytes;
        CacheOwnerTally* owner;
        const Key* key = nullptr;  ///< its map node's key
        Entry* newer = nullptr;    ///< towards the most recently used
        Entry* older = nullptr;
    };

public:
    /// Cost of one entry's bookkeeping as allocated: the map node (key,
    /// entry, next pointer and cached hash) with malloc's header and
    /// rounding, and a bucket slot. What the value owns besides is passed by
    /// the build.
    static constexpr std::size_t k_entry_bytes =
        (sizeof(std::pair<const Key, Entry>) + 2 * sizeof(void*) + 8 + 15) / 16 * 16 + sizeof(void*);
    static constexpr std::size_t k_shards = 64;
    /// The working limit a cache starts with (or its budget, if lower).
    /// Lower starts overshoot: from 4 MB the blob5k views settle near 5 MB,
    /// but the fine vase's early re-misses doubled it to 22-31 MB in most
    /// runs on 2 threads (from 8 MB: 11.5 MB in every run); from 2 MB, 10.8
    /// MB (docs/benchmarks.md, "A cache that starts at 4 MB: dropped").
    static constexpr std::size_t k_start_limit = std::size_t{8} << 20;
    /// Re-misses are frequent above one in this many misses (grow_limit).
    static constexpr std::uint64_t k_frequent_remisses = 32;

    /// With `whole_budget`, the limit is the budget from the start (a cache
    /// that must keep everything it can, as the tests' references do).
    explicit ShardedLruCache(std::size_t budget_bytes, bool whole_budget = false) : shards_(k_shards) {
        budget_.store(budget_bytes, std::memory_order_relaxed);
        limit_.store(whole_budget ? budget_bytes : std::min(budget_bytes, k_start_limit), std::memory_order_relaxed);
    }

    /// Sets the ceiling; the working limit is lowered to it if above (and
    /// grows again only up to it).
    void set_budget(std::size_t budget_bytes) {
        budget_.store(budget_bytes, std::memory_order_relaxed);
        if (limit() > budget_bytes) limit_.store(budget_bytes, std::memory_order_relaxed);
    }
    std::size_t budget() const { return budget_.load(std::memory_order_relaxed); }
    std::size_t limit() const { return limit_.load(std::memory_order_relaxed); }

    /// The shard that holds `key`: the high bits of its hash pick it (the
    /// shard's map uses all of them).
    static std::size_t shard_index(const Key& key) { return (Hash{}(key) >> 7) % k_shards; }

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
        std::shared_ptr<PendingBuild> other_build;
        std::size_t other_index = 0;
        std::shared_ptr<PendingBuild> pending;  // this thread's build, on a miss
        std::size_t needed_bytes = 0, entry_bytes = 0;  // set by a re-miss
        {
            std::lock_guard<std::mutex> lock(s.mutex);
            auto it = s.map.find(key);
            if (it != s.map.end()) {
                ++s.hits;
                owner.hits.fetch_add(1, std::memory_order_relaxed);
                s.make_newest(it->second);
                return it->second.value;
            }
            auto p = s.pending.find(key);
            if (p != s.pending.end()) {
                ++s.waits;
                owner.hits.fetch_add(1, std::memory_order_relaxed);
                other_build = p->second.build;
                other_index = p->second.index;
            } else {
                ++s.misses;
                owner.misses.fetch_add(1, std::memory_order_relaxed);
                const auto ghost = std::find(s.ghosts.begin(), s.ghosts.end(), Hash{}(key));
                if (ghost != s.ghosts.end()) {
                    ++s.remisses;
                    // The room the whole cache would have needed to keep it:
                    // this shard's bytes and, of its average entry size, one
                    // for each eviction since, times the shards.
                    const std::size_t evicted_since = static_cast<std::size_t>(s.ghosts.end() - ghost);
                    const std::size_t entry = s.bytes / std::max<std::size_t>(1, s.map.size());
                    needed_bytes = (s.bytes + evicted_since * entry) * shards_.size();
                    entry_bytes = entry;
                }
                // One pending build for the key and the group's keys claimed
                // below (allocated on a miss only).
                pending = std::make_shared<PendingBuild>();
                s.pending.emplace(key, PendingSlot{pending, 0});
            }
        }
        if (other_build) return other_build->wait(other_index);
        const std::uint64_t misses = all_misses_.fetch_add(1, std::memory_order_relaxed) + 1;
        if (needed_bytes != 0) {
            const std::uint64_t remisses = all_remisses_.fetch_add(1, std::memory_order_relaxed) + 1;
            grow_limit(needed_bytes, entry_bytes, k_frequent_remisses * remisses > misses);
        }

        // This thread builds `key`, and the group's keys nobody has or builds.
        std::vector<Key> claimed{key};
        for (const Key& k : group()) {
            if (k == key) continue;
            Shard& g = shard_for(k);
            std::lock_guard<std::mutex> lock(g.mutex);
            if (g.map.count(k) != 0 || g.pending.count(k) != 0) continue;
            g.pending.emplace(k, PendingSlot{pending, static_cast<std::uint32_t>(claimed.size())});
            claimed.push_back(k);
        }
        std::vector<std::pair<Value, std::size_t>> built;
        try {
            built = build(claimed);
            if (built.size() != claimed.size()) throw std::logic_error("cache: a group build returned a wrong count");
        } catch (...) {
            pending->fail(std::current_exception());
            for (const Key& k : claimed) {
                Shard& g = shard_for(k);
                std::lock_guard<std::mutex> lock(g.mutex);
                g.pending.erase(k);
            }
            throw;
        }
        {
            std::vector<Value> values;
            values.reserve(built.size());
            for (const auto& b : built) values.push_back(b.first);
            pending->finish(std::move(values));
        }
        for (std::size_t k = 0; k < claimed.size(); ++k) {
            Shard& g = shard_for(claimed[k]);
            std::lock_guard<std::mutex> lock(g.mutex);
            g.pending.erase(claimed[k]);
            insert_locked(g, claimed[k], built[k].first, built[k].second, owner);
        }
        return built[0].first;
    }

    /// Charges the entry under `key` for the `owned_bytes` its value owns
    /// now (it grew or shrank), if it is cached and is(value) holds (not a
    /// rebuilt value under the same key); may evict to keep the budget.
    /// The size, not a change of it: a value may change between its build
    /// and its insertion, or on another thread, where a change would be
    /// lost, and a later shrink by more than the entry was charged wrapped
    /// the shard's count round to nearly 2^64, so the shard evicted all but
    /// its last entries (seen as a flaky eviction count under TSan).
    template <class Is>
    void recharge(const Key& key, Is is, std::size_t owned_bytes) {
        Shard& s = shard_for(key);
        std::lock_guard<std::mutex> lock(s.mutex);
        auto it = s.map.find(key);
        if (it == s.map.end() || !is(it->second.value)) return;
        Entry& e = it->second;
        CacheOwnerTally& owner = *e.owner;  // the entry itself may be evicted below
        // Every count holds e.bytes, so moving them by (cost - e.bytes) in
        // unsigned arithmetic lands exactly, never below zero.
        const std::size_t cost = k_entry_bytes + owned_bytes;
        const std::size_t change = cost - e.bytes;
        e.bytes = cost;
        s.bytes += change;
        total_bytes_.fetch_add(change, std::memory_order_relaxed);
        owner.bytes.fetch_add(change, std::memory_order_relaxed);
        evict_over_budget_locked(s);
        atomic_raise(peak_bytes_, total_bytes_.load(std::memory_order_relaxed));
        atomic_raise(owner.peak_bytes, owner.bytes.load(std::memory_order_relaxed));
    }

    /// Drops every entry charged to `owner` (not counted as evictions). No
    /// thread may be building an entry for it.
    void erase_owner(const CacheOwnerTally& owner) {
        for (Shard& s : shards_) {
            std::lock_guard<std::mutex> lock(s.mutex);
            for (Entry* e = s.newest; e != nullptr;) {
                Entry* older = e->older;
                if (e->owner == &owner) {
                    s.bytes -= e->bytes;
                    total_bytes_.fetch_sub(e->bytes, std::memory_order_relaxed);
                    s.erase(*e);
                }
                e = older;
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
            c.remisses += s.remisses;
        }
        c.bytes = total_bytes_.load(std::memory_order_relaxed);
        c.peak_bytes = peak_bytes_.load(std::memory_order_relaxed);
        c.limit = limit();
        return c;
    }

private:
    /// One build in progress, for every key it claimed: the values once it
    /// is done, and where the threads that asked for one meanwhile wait.
    /// One per build, not a std::promise per key: a promise's shared state
    /// and call_once were about 6% of a close-up's time.
    class PendingBuild {
    public:
        /// The value of claimed key `index` once the build is done, or its
        /// exception rethrown.
        Value wait(std::size_t index) {
            std::unique_lock<std::mutex> lock(mutex_);
            done_cv_.wait(lock, [this] { return done_; });
            if (error_) std::rethrow_exception(error_);
            return values_[index];
        }
        void finish(std::vector<Value> values) {
            {
                std::lock_guard<std::mutex> lock(mutex_);
                values_ = std::move(values);
                done_ = true;
            }
            done_cv_.notify_all();
        }
        void fail(std::exception_ptr error) {
            {
                std::lock_guard<std::mutex> lock(mutex_);
                error_ = std::move(error);
                done_ = true;
            }
            done_cv_.notify_all();
        }

    private:
        std::mutex mutex_;
        std::condition_variable done_cv_;
        bool done_ = false;
        std::exception_ptr error_;
        std::vector<Value> values_;  ///< by claimed index
    };
    struct PendingSlot {
        std::shared_ptr<PendingBuild> build;
        std::uint32_t index;  ///< among the build's claimed keys
    };
    struct Shard {
        mutable std::mutex mutex;
        /// The entries, linked through themselves from the most recently
        /// used (newest) to the least (oldest): one node per entry, where a
        /// std::list beside the map was a second node and a second key
        /// (40 bytes more per tile).
        std::unordered_map<Key, Entry, Hash> map;
        Entry* newest = nullptr;
        Entry* oldest = nullptr;

        void unlink(Entry& e) {
            (e.newer ? e.newer->older : newest) = e.older;
            (e.older ? e.older->newer : oldest) = e.newer;
            e.newer = e.older = nullptr;
        }
        void push_newest(Entry& e) {
            e.older = newest;
            e.newer = nullptr;
            (newest ? newest->newer : oldest) = &e;
            newest = &e;
        }
        void make_newest(Entry& e) {
            if (newest == &e) return;
            unlink(e);
            push_newest(e);
        }
        void erase(Entry& e) {
            unlink(e);
            const Key key = *e.key;  // a copy: the node that holds it goes
            map.erase(key);
        }
        /// Keys being built, with the build that fulfils them.
        std::unordered_map<Key, PendingSlot, Hash> pending;
        std::uint64_t hits = 0, misses = 0, waits = 0, duplicate_builds = 0, insertions = 0,
                      evictions = 0, remisses = 0;
        std::size_t bytes = 0;
        /// The hashes of the keys evicted last, oldest first: 8 bytes each,
        /// searched only on a miss (a scan of a few hundred, against the
        /// tens of microseconds of the build that follows). A hash, not the
        /// key: a collision only counts a re-miss too many.
        std::deque<std::size_t> ghosts;
    };
    /// A shard remembers k_ghosts_per_entry evicted keys per entry it holds,
    /// and at least k_min_ghosts: a set that comes back within that many
    /// times the cache's size is seen to come back (with only as many
    /// ghosts as entries, as ARC keeps, a scan of more than twice the cache
    /// would never re-miss and never grow it).
    static constexpr std::size_t k_ghosts_per_entry = 4;
    static constexpr std::size_t k_min_ghosts = 64;
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
        const auto placed = s.map.emplace(key, Entry{value, cost, &owner});
        Entry& entry = placed.first->second;
        entry.key = &placed.first->first;
        s.push_newest(entry);
        s.bytes += cost;
        ++s.insertions;
        total_bytes_.fetch_add(cost, std::memory_order_relaxed);
        const std::size_t owner_bytes = owner.bytes.fetch_add(cost, std::memory_order_relaxed) + cost;
        evict_over_budget_locked(s);
        // Peaks after this insertion's evictions: what stays charged.
        atomic_raise(peak_bytes_, total_bytes_.load(std::memory_order_relaxed));
        atomic_raise(owner.peak_bytes, std::min(owner_bytes, owner.bytes.load(std::memory_order_relaxed)));
    }

    /// Raises the limit after a re-miss, never past the budget: by one
    /// entry's room while re-misses are rare (the cache is about the size its
    /// lookups need, and this brings it there without overshooting); while
    /// they are frequent, to what the re-missed entry needed (its LRU stack
    /// distance in bytes), at most doubling it at a time (each re-miss then
    /// costs a rebuild that may be large: a tile and the parents it starts
    /// from). Racy by design: concurrent raises only keep the larger.
    void grow_limit(std::size_t needed_bytes, std::size_t entry_bytes, bool frequent) {
        const std::size_t ceiling = budget();
        std::size_t now = limit();
        while (now < ceiling) {
            const std::size_t target = frequent ? std::min(needed_bytes, 2 * now) : now + entry_bytes;
            const std::size_t grown = std::min(ceiling, std::max(target, now + entry_bytes));
            if (limit_.compare_exchange_weak(now, grown, std::memory_order_relaxed)) return;
        }
    }

    /// Remembers an evicted key (its hash), forgetting the oldest beyond
    /// k_ghosts_per_entry per entry the shard holds.
    void remember_evicted_locked(Shard& s, const Key& key) {
        s.ghosts.push_back(Hash{}(key));
        while (s.ghosts.size() > std::max(k_min_ghosts, k_ghosts_per_entry * s.map.size())) s.ghosts.pop_front();
    }

    /// Drops the least recently used entries while the shard is over its
    /// share of the working limit.
    void evict_over_budget_locked(Shard& s) {
        const std::size_t shard_budget = limit() / shards_.size();
        while (s.bytes > shard_budget && s.map.size() > k_min_entries) {
            Entry& victim = *s.oldest;
            remember_evicted_locked(s, *victim.key);
            s.bytes -= victim.bytes;
            total_bytes_.fetch_sub(victim.bytes, std::memory_order_relaxed);
            victim.owner->bytes.fetch_sub(victim.bytes, std::memory_order_relaxed);
            victim.owner->evictions.fetch_add(1, std::memory_order_relaxed);
            s.erase(victim);
            ++s.evictions;
        }
    }

    Shard& shard_for(const Key& key) { return shards_[shard_index(key)]; }

    std::vector<Shard> shards_;
    std::atomic<std::size_t> budget_{0};  ///< the ceiling
    std::atomic<std::size_t> limit_{0};   ///< what the shards keep now, summed (each a 1/k_shards share)
    std::atomic<std::uint64_t> all_misses_{0};    ///< lookups that built, in the cache's life
    std::atomic<std::uint64_t> all_remisses_{0};  ///< of them, re-misses
    std::atomic<std::size_t> total_bytes_{0};
    std::atomic<std::size_t> peak_bytes_{0};
};

}  // namespace subdivtrace::detail

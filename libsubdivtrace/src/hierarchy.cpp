#include "subdivtrace/hierarchy.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "base_topology.h"
#include "face_chunks.h"
#include "root_records.h"
#include "tile.h"
#include "tile_cache_impl.h"

namespace subdivtrace {

namespace {

std::atomic<std::uint64_t> g_next_hierarchy_id{1};

}  // namespace

namespace detail {

/// What the threads' fronts hold of one hierarchy, shared with its tiles so a
/// front that outlives the hierarchy still has somewhere to report to.
struct FrontTally {
    std::atomic<std::size_t> fronts{0};      ///< threads holding at least one of its tiles
    std::atomic<std::size_t> tile_bytes{0};  ///< tiles held, each front counting its own
    std::atomic<std::size_t> below_bytes{0}; ///< levels tiles start from held (BelowParents, ChunkLevels)
};

/// A tile as the cache holds it, with the bytes it is charged (computed once,
/// at build time, before any other thread can see it): what the tile holds,
/// and this wrapper's share of its make_shared block (the byte count, the
/// control block's vtable pointer and two counts, malloc's header).
struct CachedTile {
    static constexpr std::size_t k_wrapper_bytes = sizeof(std::size_t) + 16 + 8;
    CachedTile(const TileContext& ctx, const NodeId& root, TileGroup& group)
        : tile(ctx, root, group), bytes(tile.bytes_held() + k_wrapper_bytes) {}
    Tile tile;
    std::size_t bytes;
};

}  // namespace detail

using detail::CachedTile;
using detail::FrontTally;

namespace {

/// A few tiles per thread in front of the shared cache: a ray's neighbours
/// descend through the same tiles, and this spares them the shared cache's
/// lock. A tile's values never change once computed (lazy levels are added
/// under its own lock), so a thread holding one cannot see a value the cache
/// would not give. One front per thread serves every hierarchy (a scene's
/// rays move between surfaces all the time); slots are keyed by the
/// hierarchy's id, never reused, as well as the tile, so a slot can never
/// answer for another surface, nor for a destroyed one's successor.
struct Front {
    static constexpr std::size_t k_slots = 64;
    /// The slot of hierarchy `owner`'s tile `root`: one multiply of the
    /// fields mixed, its top six bits (the shared cache's TileKeyHash mixes
    /// three times as the shards need, and was half of a lookup here).
    static std::size_t slot_of(std::uint64_t owner, const NodeId& root) {
        const std::uint64_t fields = (std::uint64_t{root.face} * 0x9E3779B1u) ^ (std::uint64_t{root.i} << 21) ^
                                     (std::uint64_t{root.j} << 42) ^ (std::uint64_t{root.level} << 3) ^
                                     (root.down ? 1u : 0u) ^ (owner << 56);
        static_assert(k_slots == 64, "six bits");
        return static_cast<std::size_t>((fields * 0x9E3779B97F4A7C15ULL) >> 58);
    }
    struct Slot {
        std::uint64_t owner = 0;
        NodeId root;
        std::shared_ptr<const CachedTile> tile;
        /// The owner's tally, kept alive while the slot counts in it (a
        /// thread may outlive the surface; the slot, not each tile, holds it).
        std::shared_ptr<FrontTally> tally;
    };
    std::array<Slot, k_slots> slots;
    /// Slots each hierarchy holds here, so a thread counts once per hierarchy.
    std::vector<std::pair<std::uint64_t, std::uint32_t>> holders;

    void add_holder(std::uint64_t owner, FrontTally& tally, std::size_t bytes) {
        tally.tile_bytes.fetch_add(bytes, std::memory_order_relaxed);
        for (auto& h : holders)
            if (h.first == owner) {
                ++h.second;
                return;
            }
        holders.emplace_back(owner, 1);
        tally.fronts.fetch_add(1, std::memory_order_relaxed);
    }

    void drop(Slot& slot) {
        if (!slot.tile) return;
        FrontTally& tally = *slot.tally;
        tally.tile_bytes.fetch_sub(slot.tile->bytes, std::memory_order_relaxed);
        for (std::size_t k = 0; k < holders.size(); ++k) {
            if (holders[k].first != slot.owner) continue;
            if (--holders[k].second == 0) {
                holders[k] = holders.back();
                holders.pop_back();
                tally.fronts.fetch_sub(1, std::memory_order_relaxed);
            }
            break;
        }
        slot.tile.reset();
        slot.tally.reset();
    }

    ~Front() {
        for (auto& slot : slots) drop(slot);
    }
};

/// The level below a parent tile's deepest one (Tile::below_deepest), kept
/// by each thread for the parent's next children (tile.h, LevelBelow): the
/// rays that reach one child mostly reach its siblings soon after, on the
/// same thread, and the parent tile does not keep it (it is about 3x the
/// rest of the tile). The bunny close-up computed 1,016 for 13 k child
/// tiles with 32 slots (4,223 with 8, 3,003 with 16, 726 with 64): a row of
/// pixels crosses about that many parents before the next row comes back
/// to them. Keyed like the front, by hierarchy id and tile root: whichever
/// build of the parent computed it, its bits are the same. Its bytes count
/// apart from the fronts' (HierarchyCounters::below_bytes).
struct BelowParents {
    static constexpr std::size_t k_slots = 32;
    /// Levels kept finished at once, the most recently built from: a
    /// finished level holds about 4x its bytes.
    static constexpr std::size_t k_finished = 8;
    /// Groups started from a level's own bands before it is finished.
    static constexpr std::uint32_t k_groups_before_finishing = 4;
    struct Slot {
        std::uint64_t owner = 0;
        NodeId root;
        std::shared_ptr<FrontTally> tally;  ///< set while the slot holds a level
        std::size_t bytes = 0;
        std::unique_ptr<detail::LevelBelow> level;
        std::uint64_t last_built = 0;  ///< when a tile group last started from it
        std::uint32_t groups_started = 0;  ///< tile groups started from it since it was last unfinished
    };
    std::array<Slot, k_slots> slots;
    std::size_t next = 0;  ///< the slot replaced next (round robin)
    std::uint64_t groups = 0;  ///< tile groups started so far

    /// The slot holding the level below tile `root`'s deepest, if this thread has it.
    Slot* slot_of(std::uint64_t owner, const NodeId& root) {
        for (Slot& s : slots)
            if (s.tally && s.owner == owner && s.root == root) return &s;
        return nullptr;
    }
    /// The level below tile `root`'s deepest, if this thread has it.
    const detail::LevelBelow* find(std::uint64_t owner, const NodeId& root) {
        const Slot* s = slot_of(owner, root);
        return s ? s->level.get() : nullptr;
    }

    /// The slot holding the level below tile `root`'s deepest, computed if
    /// this thread has it not.
    Slot& of(std::uint64_t owner, const NodeId& root, const detail::Tile& parent,
             const std::shared_ptr<FrontTally>& tally) {
        if (Slot* found = slot_of(owner, root)) return *found;
        Slot& s = slots[next];
        next = (next + 1) % k_slots;
        release(s);
        s.level = std::make_unique<detail::LevelBelow>(parent.below_deepest());
        s.owner = owner;
        s.root = root;
        s.bytes = s.level->owned_bytes();
        s.tally = tally;
        tally->below_bytes.fetch_add(s.bytes, std::memory_order_relaxed);
        return s;
    }

    /// Whether tile groups start from `level` itself (finishing it, if it
    /// is not), or from their own band cut from it: a parent's first child
    /// tiles are often its only ones (a silhouette, another object's
    /// shadow ray), and finishing the whole level for one or two of them
    /// cost more than it saved (POV-Ray's twenty bunnies: 1.07x the CPU).
    static bool worth_finishing(const Slot& s) {
        return s.level->finished() || s.groups_started >= k_groups_before_finishing;
    }

    /// Before a tile group starts from slot `s`'s level itself: if it is
    /// not finished and k_finished others are, the one least recently
    /// started from is unfinished.
    void make_room(const Slot& s) {
        if (s.level->finished()) return;
        std::size_t finished = 0;
        Slot* oldest = nullptr;
        for (Slot& other : slots) {
            if (!other.level || !other.level->finished()) continue;
            ++finished;
            if (!oldest || other.last_built < oldest->last_built) oldest = &other;
        }
        if (finished < k_finished || !oldest) return;
        oldest->level->unfinish();
        oldest->groups_started = 0;  // finished again only if it serves more groups
        recharge(*oldest);
    }

    /// After a tile group started from slot `s`'s level: it is the most
    /// recent, and charged what it holds now (it grows as child tiles are
    /// built from it).
    void started(Slot& s) {
        s.last_built = ++groups;
        ++s.groups_started;
        recharge(s);
    }

    static void recharge(Slot& s) {
        if (!s.tally) return;
        const std::size_t now = s.level->owned_bytes();
        s.tally->below_bytes.fetch_add(now, std::memory_order_relaxed);
        s.tally->below_bytes.fetch_sub(s.bytes, std::memory_order_relaxed);
        s.bytes = now;
    }

    static void release(Slot& s) {
        if (s.tally) s.tally->below_bytes.fetch_sub(s.bytes, std::memory_order_relaxed);
        s.tally.reset();
        s.level.reset();
    }

    ~BelowParents() {
        for (Slot& s : slots) release(s);
    }

    /// This thread's.
    static BelowParents& mine() {
        thread_local BelowParents below;
        return below;
    }
};

/// A chunk's level 1 (detail::chunk_level), where its base triangles'
/// tiles start, as every thread shares it: held by ChunkLevels and by the
/// builds that use it, and charged to its hierarchy's tally
/// (HierarchyCounters::below_bytes) while it lives.
struct ChunkStart {
    explicit ChunkStart(std::shared_ptr<FrontTally> tally_) : tally(std::move(tally_)) {}
    ~ChunkStart() { tally->below_bytes.fetch_sub(bytes, std::memory_order_relaxed); }
    ChunkStart(const ChunkStart&) = delete;
    ChunkStart& operator=(const ChunkStart&) = delete;
    /// Held while the level is computed and while a tile is built from it
    /// (a build finishes it and adds the next level's points it reads).
    std::mutex lock;
    std::unique_ptr<detail::LevelBelow> level;
    std::size_t bytes = 0;  ///< charged to the tally (under `lock`)
    std::shared_ptr<FrontTally> tally;

    /// Charges what the level holds now (under `lock`).
    void recharge() {
        const std::size_t now = level ? level->owned_bytes() : 0;
        tally->below_bytes.fetch_add(now, std::memory_order_relaxed);
        tally->below_bytes.fetch_sub(bytes, std::memory_order_relaxed);
        bytes = now;
    }
};

/// The chunks' levels most recently started from, of every hierarchy, for
/// all threads: a chunk's tiles are asked for by whichever thread's rays
/// reach its faces first, and a level kept per thread was computed and
/// finished once by each (the blob5k close-up on 2 threads took 1.04x the
/// CPU of building a chunk's 16 tiles at once, and 3.7 MiB more).
class ChunkLevels {
public:
    /// Levels kept at once, all finished (a finished level of 16 faces
    /// holds about 200 kB). Rows of pixels cross many chunks before the
    /// next rows come back to them: the fine vase (320x240, one thread)
    /// took 5.53 G instructions with 16, 5.09 G with 32, 5.08 G with 64.
    static constexpr std::size_t k_capacity = 32;

    /// Chunk `chunk` of hierarchy `owner`, made (without its level) if none is kept.
    std::shared_ptr<ChunkStart> get(std::uint64_t owner, std::uint32_t chunk,
                                    const std::shared_ptr<FrontTally>& tally) {
        const std::lock_guard<std::mutex> hold(mutex_);
        if (Slot* s = used(owner, chunk)) return s->start;
        Slot* oldest = nullptr;
        for (Slot& s : slots_)
            if (!oldest || s.last_used < oldest->last_used) oldest = &s;
        Slot fresh{owner, chunk, clock_, std::make_shared<ChunkStart>(tally)};
        if (slots_.size() < k_capacity) slots_.push_back(fresh);
        else *oldest = fresh;  // the replaced level goes once no build holds it
        return fresh.start;
    }

    /// Chunk `chunk` of hierarchy `owner` if one is kept (with or without its level).
    std::shared_ptr<ChunkStart> find(std::uint64_t owner, std::uint32_t chunk) {
        const std::lock_guard<std::mutex> hold(mutex_);
        Slot* s = used(owner, chunk);
        return s ? s->start : nullptr;
    }

    /// Drops the levels of a hierarchy nobody can ask for again.
    void erase_owner(std::uint64_t owner) {
        const std::lock_guard<std::mutex> hold(mutex_);
        slots_.erase(std::remove_if(slots_.begin(), slots_.end(), [&](const Slot& s) { return s.owner == owner; }),
                     slots_.end());
    }

    static ChunkLevels& instance() {
        static ChunkLevels levels;
        return levels;
    }

private:
    struct Slot {
        std::uint64_t owner;
        std::uint32_t chunk;
        std::uint64_t last_used;
        std::shared_ptr<ChunkStart> start;
    };
    /// The kept slot of chunk `chunk` of `owner`, marked used now, or null
    /// (under mutex_; the clock ticks either way).
    Slot* used(std::uint64_t owner, std::uint32_t chunk) {
        ++clock_;
        for (Slot& s : slots_)
            if (s.owner == owner && s.chunk == chunk) {
                s.last_used = clock_;
                return &s;
            }
        return nullptr;
    }

    std::mutex mutex_;
    std::vector<Slot> slots_;
    std::uint64_t clock_ = 0;
};

}  // namespace

class HierarchyImpl {
public:
    HierarchyImpl(const Mesh& mesh, SchemeKind scheme, int max_level,
                  std::shared_ptr<TileCache> shared_cache, ShellKind shell_kind)
        : topo(mesh),
          context{topo, detail::rules_of(scheme), shell_kind, max_level, &nodes_built, &tile_build_ns, nullptr, {}, {}, {}},
          roots(context),
          cache(std::move(shared_cache)),
          tiles(cache->impl()) {
        context.roots = &roots;
        // A tile that grows is charged its new size (if the cache still
        // holds that very tile: a rebuilt one under its key is not it).
        context.resized = [this](const detail::Tile& t, const NodeId& root, std::size_t bytes) {
            tiles.recharge(
                detail::TileKey{id, root}, [&](const std::shared_ptr<const CachedTile>& v) { return &v->tile == &t; },
                bytes + CachedTile::k_wrapper_bytes);
        };
        context.child_start = [this](const NodeId& root) {
            // Cut from the level below the parent where this thread has it
            // (the group's own start, cheaper than splitting the parent's band).
            const NodeId parent_root = detail::parent_tile_root(root);
            if (const detail::LevelBelow* below = BelowParents::mine().find(id, parent_root))
                return detail::band_of_roots(below->patch(), {root});
            return tile(parent_root)->tile.band_of_child(root);
        };
        context.base_start = [this](std::uint32_t face) -> std::optional<detail::Patch> {
            // Cut from its chunk's level 1 where one is kept (every thread
            // shares them): a level of the face alone is a base patch of
            // about 49 faces split once.
            if (const std::shared_ptr<ChunkStart> chunk =
                    ChunkLevels::instance().find(id, chunks_of_faces().chunk_index(face))) {
                const std::lock_guard<std::mutex> hold(chunk->lock);
                if (chunk->level) return detail::band_of_roots(chunk->level->patch(), {root_node(face)});
            }
            return std::nullopt;
        };
        tiles.surfaces.fetch_add(1, std::memory_order_relaxed);
    }

    ~HierarchyImpl() {
        // The tiles of a surface nobody can ask for again leave the shared
        // cache now rather than when they age out.
        tiles.erase_owner(share);
        ChunkLevels::instance().erase_owner(id);
        tiles.surfaces.fetch_sub(1, std::memory_order_relaxed);
    }

    /// The tile rooted at `root`, from this thread's front: valid until this
    /// thread's next call.
    const detail::Tile* front_tile(const NodeId& root) {
        thread_local Front front;
        Front::Slot& slot = front.slots[Front::slot_of(id, root)];
        if (slot.tile && slot.owner == id && slot.root == root) return &slot.tile->tile;
        std::shared_ptr<const CachedTile> t = tile(root);
        front.drop(slot);
        front.add_holder(id, *front_tally, t->bytes);
        slot.owner = id;
        slot.root = root;
        slot.tile = std::move(t);
        slot.tally = front_tally;
        return &slot.tile->tile;
    }

    /// The tile from the shared cache, built by this thread if no other has
    /// it or is building it (with the tiles of its group below a tile that
    /// no thread has or builds, where k_group_levels makes groups), from the
    /// level it starts from (a chunk's, ChunkLevels; the level below its
    /// parent's deepest, BelowParents).
    std::shared_ptr<const CachedTile> tile(const NodeId& root) {
        const auto group = [&] {
            std::vector<detail::TileKey> keys;
            if (root.level > 0)
                for (const NodeId& r : detail::tile_group_of(root)) keys.push_back({id, r});
            return keys;
        };
        const auto build = [&](const std::vector<detail::TileKey>& claimed) {
            std::vector<NodeId> roots;
            for (const detail::TileKey& k : claimed) roots.push_back(k.root);
            const auto build_from = [&](detail::TileGroup& start) {
                std::vector<std::pair<std::shared_ptr<const CachedTile>, std::size_t>> built;
                for (const NodeId& r : roots) {
                    auto t = std::make_shared<const CachedTile>(context, r, start);
                    built.emplace_back(t, t->bytes);
                }
                tiles_built.fetch_add(built.size(), std::memory_order_relaxed);
                return built;
            };
            if (root.level == 0) {
                // From its chunk's level 1, which every thread shares.
                const detail::FaceChunks& chunks = chunks_of_faces();
                const std::shared_ptr<ChunkStart> chunk =
                    ChunkLevels::instance().get(id, chunks.chunk_index(root.face), front_tally);
                const std::lock_guard<std::mutex> hold(chunk->lock);
                if (!chunk->level) {
                    const auto [begin, end] = chunks.chunk_of(root.face);
                    chunk->level = std::make_unique<detail::LevelBelow>(
                        detail::chunk_level(context, begin, static_cast<std::size_t>(end - begin)));
                }
                detail::TileGroup start(context, *chunk->level, roots);
                auto built = build_from(start);
                chunk->recharge();
                return built;
            }
            // A tile below a tile starts from the level below the parent's
            // deepest one, which this thread keeps for recent parents (the
            // parent is rebuilt in turn if it was evicted: values never
            // depend on the cache).
            const NodeId parent_root = detail::parent_tile_root(root);
            const std::shared_ptr<const CachedTile> parent = tile(parent_root);
            BelowParents& below = BelowParents::mine();
            BelowParents::Slot& slot = below.of(id, parent_root, parent->tile, front_tally);
            std::unique_ptr<detail::LevelBelow> own_band;  // outlives `start`, which may read it
            std::unique_ptr<detail::TileGroup> start;
            if (BelowParents::worth_finishing(slot)) {
                below.make_room(slot);
                start = std::make_unique<detail::TileGroup>(context, *slot.level, roots);
            } else {
                own_band = std::make_unique<detail::LevelBelow>(detail::band_of_roots(slot.level->patch(), roots));
                start = std::make_unique<detail::TileGroup>(context, *own_band, roots);
            }
            below.started(slot);
            return build_from(*start);
        };
        return tiles.lookup_or_build_group(detail::TileKey{id, root}, share, group, build);
    }

    /// Never reused, so keys and fronts cannot confuse two hierarchies.
    const std::uint64_t id = g_next_hierarchy_id.fetch_add(1);

    std::atomic<std::uint64_t> nodes_built{0};
    std::atomic<std::uint64_t> tiles_built{0};
    /// Time spent building tiles, their lazy levels and the bands child
    /// tiles start from (not waiting for another thread), summed over threads.
    std::atomic<std::uint64_t> tile_build_ns{0};
    detail::BaseTopology topo;
    detail::TileContext context;
    detail::RootRecords roots;
    /// Base faces by chunk (the faces whose tiles start from one level),
    /// made when the first base triangle's tile is.
    const detail::FaceChunks& chunks_of_faces() {
        std::call_once(chunks_built, [&] {
            chunks = std::make_unique<detail::FaceChunks>(topo, detail::k_face_chunk_size);
            chunk_bytes.store(chunks->owned_bytes(), std::memory_order_relaxed);
        });
        return *chunks;
    }
    std::once_flag chunks_built;
    std::unique_ptr<detail::FaceChunks> chunks;
    std::atomic<std::size_t> chunk_bytes{0};  ///< for counters(), which may run meanwhile
    std::shared_ptr<TileCache> cache;
    detail::TileCacheImpl& tiles;
    /// This hierarchy's share of the cache (its entries point here).
    detail::CacheOwnerTally share;
    std::shared_ptr<FrontTally> front_tally = std::make_shared<FrontTally>();
};

namespace {

std::shared_ptr<TileCache> cache_or_own(std::shared_ptr<TileCache> cache, std::size_t cache_bytes) {
    return cache ? std::move(cache) : std::make_shared<TileCache>(cache_bytes);
}

}  // namespace

Hierarchy::Hierarchy(const Mesh& mesh, SchemeKind scheme, int max_level,
                     std::size_t cache_bytes, ShellKind shell_kind)
    : impl_(std::make_unique<HierarchyImpl>(mesh, scheme, max_level,
                                            cache_or_own(nullptr, cache_bytes), shell_kind)) {}

Hierarchy::Hierarchy(const Mesh& mesh, SchemeKind scheme, int max_level,
                     std::shared_ptr<TileCache> cache, ShellKind shell_kind)
    : impl_(std::make_unique<HierarchyImpl>(
          mesh, scheme, max_level, cache_or_own(std::move(cache), TileCache::k_default_mb << 20),
          shell_kind)) {}

Hierarchy::~Hierarchy() = default;

SchemeKind Hierarchy::scheme() const { return impl_->context.scheme.kind; }
int Hierarchy::max_level() const { return impl_->context.max_level; }
std::size_t Hierarchy::face_count() const { return impl_->topo.face_count(); }
bool Hierarchy::closed() const { return impl_->topo.closed(); }
const std::shared_ptr<TileCache>& Hierarchy::cache() const { return impl_->cache; }

NodeRecord Hierarchy::node(const NodeId& id, Part part) const {
    const bool normals = part == Part::all;
    if (id.level == 0) return impl_->roots.record(id.face, normals, part != Part::corners);
    return impl_->front_tile(detail::tile_root_of(id))->record(id, normals, part != Part::corners);
}

Shell Hierarchy::root_shell(std::uint32_t face) const { return impl_->roots.shell(face); }

void Hierarchy::child_shells(const NodeId& id, std::array<Shell, 4>& out) const {
    impl_->front_tile(detail::tile_root_of(child_of(id, 0)))->child_shells(id, out);
}

void Hierarchy::children(const NodeId& id, std::array<NodeRecord, 4>& out) const {
    for (int c = 0; c < 4; ++c) out[c] = node(child_of(id, c));
}

HierarchyCounters Hierarchy::counters() const {
    const detail::CacheOwnerTally& t = impl_->share;
    HierarchyCounters c;
    c.nodes_built = impl_->nodes_built.load();
    c.tiles_built = impl_->tiles_built.load();
    c.tile_build_seconds = static_cast<double>(impl_->tile_build_ns.load()) * 1e-9;
    c.node_hits = t.hits.load(std::memory_order_relaxed);
    c.node_misses = t.misses.load(std::memory_order_relaxed);
    c.evictions = t.evictions.load(std::memory_order_relaxed);
    c.bytes = t.bytes.load(std::memory_order_relaxed);
    c.peak_bytes = t.peak_bytes.load(std::memory_order_relaxed);
    c.topology_bytes = impl_->topo.owned_bytes() + impl_->chunk_bytes.load(std::memory_order_relaxed);
    c.root_bytes = impl_->roots.owned_bytes();
    c.fronts = impl_->front_tally->fronts.load(std::memory_order_relaxed);
    c.front_bytes = c.fronts * sizeof(Front) +
                    impl_->front_tally->tile_bytes.load(std::memory_order_relaxed);
    c.below_bytes = impl_->front_tally->below_bytes.load(std::memory_order_relaxed);
    return c;
}

}  // namespace subdivtrace

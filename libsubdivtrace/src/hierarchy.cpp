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
    std::atomic<std::size_t> below_bytes{0}; ///< levels below parent tiles held (StartLevels)
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

/// The levels tiles start from (tile.h, LevelBelow), kept by each thread
/// for the next tiles that start there. Two kinds, one instance each:
/// - the level below a parent tile's deepest one (Tile::below_deepest), for
///   the parent's next children: the rays that reach one child mostly
///   reach its siblings soon after, on the same thread, and the parent tile
///   does not keep it (it is about 3x the rest of the tile). The bunny
///   close-up computed 1,016 for 13 k child tiles with 32 slots (4,223 with
///   8, 3,003 with 16, 726 with 64): a row of pixels crosses about that
///   many parents before the next row comes back to them;
/// - a chunk's level 1 (chunk_level), for its base triangles' tiles: each
///   is built when a ray asks for it, where a chunk's 16 tiles used to be
///   built together (the fine vase built 23,918 tiles for the 15,697 its
///   rays asked for, and filled its 32 MB cache with them).
/// Keyed like the front, by hierarchy id and tile root (a chunk's: its
/// first face's): whichever thread computed a level, its bits are the same.
/// Its bytes count apart from the fronts' (HierarchyCounters::below_bytes).
struct StartLevels {
    /// Levels kept finished at once, the most recently built from: a
    /// finished level holds about 4x its bytes.
    const std::size_t max_finished;
    /// Tile groups that start from a level's own bands before it is
    /// finished (worth_finishing).
    const std::uint32_t groups_before_finishing;
    StartLevels(std::size_t slot_count, std::size_t max_finished_, std::uint32_t groups_before_finishing_)
        : max_finished(max_finished_), groups_before_finishing(groups_before_finishing_), slots(slot_count) {}
    struct Slot {
        std::uint64_t owner = 0;
        NodeId root;
        std::shared_ptr<FrontTally> tally;  ///< set while the slot holds a level
        std::size_t bytes = 0;
        std::unique_ptr<detail::LevelBelow> level;
        std::uint64_t last_built = 0;  ///< when a tile group last started from it
        std::uint32_t groups_started = 0;  ///< tile groups started from it since it was last unfinished
    };
    std::vector<Slot> slots;
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

    /// The slot holding the level keyed `root`, computed by `compute()` if
    /// this thread has it not.
    template <class Compute>
    Slot& of(std::uint64_t owner, const NodeId& root, const std::shared_ptr<FrontTally>& tally,
             Compute compute) {
        if (Slot* found = slot_of(owner, root)) return *found;
        Slot& s = slots[next];
        next = (next + 1) % slots.size();
        release(s);
        s.level = std::make_unique<detail::LevelBelow>(compute());
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
    bool worth_finishing(const Slot& s) const {
        return s.level->finished() || s.groups_started >= groups_before_finishing;
    }

    /// Before a tile group starts from slot `s`'s level itself: if it is
    /// not finished and max_finished others are, the one least recently
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
        if (finished < max_finished || !oldest) return;
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

    ~StartLevels() {
        for (Slot& s : slots) release(s);
    }

    /// This thread's levels below parent tiles, keyed by the parent's root.
    static StartLevels& below_parents() {
        thread_local StartLevels below(32, 8, 4);
        return below;
    }
    /// This thread's chunks' level 1 (detail::chunk_level), keyed by the
    /// root of the chunk's first face: where base triangles' tiles start.
    /// Finished at once and kept finished: a chunk's tiles are its faces',
    /// not a parent's few children, and rows of pixels cross many chunks
    /// (with 8 kept finished, the fine vase finished each level 2.5 times).
    static StartLevels& chunk_levels() {
        thread_local StartLevels chunks(32, 16, 0);
        return chunks;
    }
};

}  // namespace

class HierarchyImpl {
public:
    HierarchyImpl(const Mesh& mesh, SchemeKind scheme, int max_level,
                  std::shared_ptr<TileCache> shared_cache, ShellKind shell_kind)
        : topo(mesh),
          context{topo, detail::rules_of(scheme), shell_kind, max_level, &nodes_built, &tile_build_ns, nullptr, {}, {}},
          roots(context),
          cache(std::move(shared_cache)),
          tiles(cache->impl()) {
        context.roots = &roots;
        // A tile that grows is charged its new size (if the cache still
        // holds that very tile: a rebuilt one under its key is not it).
        context.resized = [this](const detail::Tile& t, const NodeId& root, std::size_t before, std::size_t after) {
            tiles.recharge(
                detail::TileKey{id, root}, [&](const std::shared_ptr<const CachedTile>& v) { return &v->tile == &t; },
                before, after);
        };
        context.child_start = [this](const NodeId& root) {
            // Cut from the level below the parent where this thread has it
            // (the group's own start, cheaper than splitting the parent's band).
            const NodeId parent_root = detail::parent_tile_root(root);
            if (const detail::LevelBelow* below = StartLevels::below_parents().find(id, parent_root))
                return detail::band_of_roots(below->patch(), {root});
            return tile(parent_root)->tile.band_of_child(root);
        };
        tiles.surfaces.fetch_add(1, std::memory_order_relaxed);
    }

    ~HierarchyImpl() {
        // The tiles of a surface nobody can ask for again leave the shared
        // cache now rather than when they age out.
        tiles.erase_owner(share);
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
    /// level this thread keeps for it and its neighbours (StartLevels).
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
            // Tiles start from a level this thread keeps for their neighbours:
            // a base triangle's from its chunk's level 1, a tile below a tile
            // from the level below the parent's deepest one (the parent is
            // rebuilt in turn if it was evicted: values never depend on the
            // cache).
            StartLevels* kept = nullptr;
            StartLevels::Slot* slot = nullptr;
            if (root.level == 0) {
                const auto [begin, end] = chunks_of_faces().chunk_of(root.face);
                kept = &StartLevels::chunk_levels();
                slot = &kept->of(id, root_node(*begin), front_tally, [&, begin = begin, end = end] {
                    return detail::chunk_level(context, begin, static_cast<std::size_t>(end - begin));
                });
            } else {
                const NodeId parent_root = detail::parent_tile_root(root);
                const std::shared_ptr<const CachedTile> parent = tile(parent_root);
                kept = &StartLevels::below_parents();
                slot = &kept->of(id, parent_root, front_tally, [&] { return parent->tile.below_deepest(); });
            }
            std::unique_ptr<detail::LevelBelow> own_band;  // outlives `start`, which may read it
            std::unique_ptr<detail::TileGroup> start;
            if (kept->worth_finishing(*slot)) {
                kept->make_room(*slot);
                start = std::make_unique<detail::TileGroup>(context, *slot->level, roots);
            } else {
                own_band = std::make_unique<detail::LevelBelow>(detail::band_of_roots(slot->level->patch(), roots));
                start = std::make_unique<detail::TileGroup>(context, *own_band, roots);
            }
            kept->started(*slot);
            std::vector<std::pair<std::shared_ptr<const CachedTile>, std::size_t>> built;
            for (const NodeId& r : roots) {
                auto t = std::make_shared<const CachedTile>(context, r, *start);
                built.emplace_back(t, t->bytes);
            }
            tiles_built.fetch_add(built.size(), std::memory_order_relaxed);
            return built;
        };
        return tiles.lookup_or_build_group(detail::TileKey{id, root}, share, group, build);
    }

    /// Never reused, so keys and fronts cannot confuse two hierarchies.
    const std::uint64_t id = g_next_hierarchy_id.fetch_add(1);

    std::atomic<std::uint64_t> nodes_built{0};
    std::atomic<std::uint64_t> tiles_built{0};
    /// Time spent building tiles, their lazy levels and the frontiers child
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

#include "subdivtrace/hierarchy.h"

#include <array>
#include <atomic>
#include <memory>

#include "grid.h"
#include "lru_cache.h"
#include "tile.h"

namespace subdivtrace {

namespace {

std::atomic<std::uint64_t> g_next_hierarchy_id{1};

struct NodeKeyHash {
    std::size_t operator()(const NodeId& n) const {
        const std::uint64_t h0 = (std::uint64_t{n.face} << 32) | (std::uint64_t{n.level} << 1) | n.down;
        const std::uint64_t h1 = (std::uint64_t{n.i} << 32) | n.j;
        return static_cast<std::size_t>(detail::mix64(h0 ^ detail::mix64(h1)));
    }
};

// Corner k of child c, for parents of each orientation (see uniform.h for
// the order; derived from the grid coordinates in child_of).
const std::array<std::array<ChildCorner, 3>, 4> k_up_children = {{
    {{{false, 0}, {true, 0}, {true, 2}}},
    {{{true, 0}, {false, 1}, {true, 1}}},
    {{{true, 2}, {true, 1}, {false, 2}}},
    {{{true, 0}, {true, 1}, {true, 2}}},
}};
const std::array<std::array<ChildCorner, 3>, 4> k_down_children = {{
    {{{false, 0}, {true, 0}, {true, 2}}},
    {{{true, 0}, {false, 1}, {true, 1}}},
    {{{true, 2}, {true, 1}, {false, 2}}},
    {{{true, 2}, {true, 0}, {true, 1}}},
}};

}  // namespace

const std::array<ChildCorner, 3>& child_corners(bool parent_down, int child) {
    return parent_down ? k_down_children[child] : k_up_children[child];
}

NodeId child_of(const NodeId& node, int child) {
    NodeId c;
    c.face = node.face;
    c.level = static_cast<std::uint8_t>(node.level + 1);
    const std::uint32_t i = 2 * node.i, j = 2 * node.j;
    if (!node.down) {
        static const std::uint32_t di[4] = {0, 1, 0, 0}, dj[4] = {0, 0, 1, 0};
        c.down = child == 3;
        c.i = i + di[child];
        c.j = j + dj[child];
    } else {
        static const std::uint32_t di[4] = {1, 1, 0, 1}, dj[4] = {0, 1, 1, 1};
        c.down = child != 3;
        c.i = i + di[child];
        c.j = j + dj[child];
    }
    return c;
}

std::array<std::array<std::uint32_t, 2>, 3> node_corner_grid(const NodeId& n) {
    if (!n.down) return {{{n.i, n.j}, {n.i + 1, n.j}, {n.i, n.j + 1}}};
    return {{{n.i + 1, n.j}, {n.i + 1, n.j + 1}, {n.i, n.j + 1}}};
}

/// A tile as the cache holds it, with the bytes it is charged (computed once,
/// at build time, before any other thread can see it).
struct CachedTile {
    CachedTile(const detail::TileContext& ctx, const NodeId& root, const detail::Patch* parent)
        : tile(ctx, root, parent), bytes(tile.bytes_when_complete()) {}
    detail::Tile tile;
    std::size_t bytes;
};

/// What the threads' fronts of one hierarchy hold, shared with the fronts so
/// a front that outlives its hierarchy still has somewhere to report to.
struct FrontTally {
    std::atomic<std::size_t> fronts{0};
    std::atomic<std::size_t> tile_bytes{0};  ///< tiles held, each front counting its own
};

class HierarchyImpl {
public:
    HierarchyImpl(const Mesh& mesh, SchemeKind scheme, int max_level, std::size_t cache_bytes,
                  ShellKind shell_kind)
        : topo(mesh),
          context{topo, scheme, shell_kind, max_level, &nodes_built},
          roots(context),
          tiles(cache_bytes) {}

    /// A few tiles per thread in front of the shared cache: a ray's
    /// neighbours descend through the same tiles, and this spares them the
    /// shared cache's lock. A tile's values never change once computed (lazy
    /// levels are added under its own lock), so a thread holding one cannot
    /// see a value the cache would not give. A front serves one hierarchy at
    /// a time; it drops its tiles when its thread moves to another or exits.
    struct Front {
        static constexpr std::size_t k_slots = 64;
        struct Slot {
            NodeId root;
            std::shared_ptr<const CachedTile> tile;
        };
        std::uint64_t owner = 0;
        std::shared_ptr<FrontTally> tally;
        std::array<Slot, k_slots> slots;

        void release() {
            if (!tally) return;
            std::size_t held = 0;
            for (auto& slot : slots) {
                if (slot.tile) held += slot.tile->bytes;
                slot.tile.reset();
            }
            tally->tile_bytes.fetch_sub(held, std::memory_order_relaxed);
            tally->fronts.fetch_sub(1, std::memory_order_relaxed);
            tally.reset();
        }
        ~Front() { release(); }
    };

    /// The tile rooted at `root`, from this thread's front: valid until this
    /// thread's next call.
    const detail::Tile* front_tile(const NodeId& root) {
        thread_local Front front;
        if (front.owner != id) {
            front.release();
            front.owner = id;
            front.tally = front_tally;
            front_tally->fronts.fetch_add(1, std::memory_order_relaxed);
        }
        auto& slot = front.slots[NodeKeyHash{}(root) % Front::k_slots];
        if (slot.tile && slot.root == root) return &slot.tile->tile;
        std::shared_ptr<const CachedTile> t = tile(root);
        front_tally->tile_bytes.fetch_add(t->bytes, std::memory_order_relaxed);
        if (slot.tile) front_tally->tile_bytes.fetch_sub(slot.tile->bytes, std::memory_order_relaxed);
        slot.root = root;
        slot.tile = std::move(t);
        return &slot.tile->tile;
    }

    std::shared_ptr<const CachedTile> tile(const NodeId& root) {
        std::shared_ptr<const CachedTile> t;
        if (!tiles.lookup(root, t)) t = build(root);
        return t;
    }

    std::shared_ptr<const CachedTile> build(const NodeId& root) {
        // A child tile starts from its parent tile's last patch (rebuilt in
        // turn if it was evicted: values never depend on the cache).
        std::shared_ptr<const CachedTile> parent;
        if (root.level > 0) parent = tile(detail::parent_tile_root(root));
        auto built = std::make_shared<const CachedTile>(
            context, root, parent ? &parent->tile.last_patch() : nullptr);
        tiles.insert(root, built, built->bytes);
        return built;
    }

    /// Never reused, so a thread's front cannot confuse two hierarchies.
    const std::uint64_t id = g_next_hierarchy_id.fetch_add(1);

    std::atomic<std::uint64_t> nodes_built{0};
    detail::BaseTopology topo;
    detail::TileContext context;
    detail::RootRecords roots;
    detail::ShardedLruCache<NodeId, std::shared_ptr<const CachedTile>, NodeKeyHash> tiles;
    std::shared_ptr<FrontTally> front_tally = std::make_shared<FrontTally>();
};

Hierarchy::Hierarchy(const Mesh& mesh, SchemeKind scheme, int max_level,
                     std::size_t cache_bytes, ShellKind shell_kind)
    : impl_(std::make_unique<HierarchyImpl>(mesh, scheme, max_level, cache_bytes, shell_kind)) {}

Hierarchy::~Hierarchy() = default;

SchemeKind Hierarchy::scheme() const { return impl_->context.scheme; }
int Hierarchy::max_level() const { return impl_->context.max_level; }
std::size_t Hierarchy::face_count() const { return impl_->topo.face_count(); }
bool Hierarchy::closed() const { return impl_->topo.closed(); }

NodeRecord Hierarchy::node(const NodeId& id) const {
    if (id.level == 0) return impl_->roots.record(id.face);
    return impl_->front_tile(detail::tile_root_of(id))->record(id);
}

void Hierarchy::children(const NodeId& id, std::array<NodeRecord, 4>& out) const {
    impl_->front_tile(detail::tile_root_of(child_of(id, 0)))->children(id, out);
}

HierarchyCounters Hierarchy::counters() const {
    const detail::CacheCounters t = impl_->tiles.counters();
    HierarchyCounters c;
    c.nodes_built = impl_->nodes_built.load();
    c.node_hits = t.hits;
    c.node_misses = t.misses;
    c.evictions = t.evictions;
    c.bytes = t.bytes;
    c.peak_bytes = t.peak_bytes;
    c.topology_bytes = impl_->topo.owned_bytes();
    c.root_bytes = impl_->roots.owned_bytes();
    c.fronts = impl_->front_tally->fronts.load(std::memory_order_relaxed);
    c.front_bytes = c.fronts * sizeof(HierarchyImpl::Front) +
                    impl_->front_tally->tile_bytes.load(std::memory_order_relaxed);
    return c;
}

}  // namespace subdivtrace

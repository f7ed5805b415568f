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

class HierarchyImpl {
public:
    HierarchyImpl(const Mesh& mesh, SchemeKind scheme, int max_level, std::size_t cache_bytes,
                  ShellKind shell_kind)
        : topo(mesh),
          context{topo, scheme, shell_kind, max_level, &nodes_built},
          roots(context),
          tiles(cache_bytes) {}

    /// The tile rooted at `root`, from this thread's front: valid until this
    /// thread's next call.
    const detail::Tile* front_tile(const NodeId& root) {
        // A few tiles per thread in front of the shared cache: a ray's
        // neighbours descend through the same tiles, and this spares them the
        // shared cache's lock. A tile's values never change once computed
        // (lazy levels are added under its own lock), so a thread holding
        // one cannot see a value the cache would not give.
        struct Front {
            std::uint64_t owner = 0;
            struct Slot {
                NodeId root;
                std::shared_ptr<const detail::Tile> tile;
            };
            std::array<Slot, 64> slots;
        };
        thread_local Front front;
        if (front.owner != id) {
            for (auto& slot : front.slots) slot.tile.reset();
            front.owner = id;
        }
        auto& slot = front.slots[NodeKeyHash{}(root) % front.slots.size()];
        if (slot.tile && slot.root == root) return slot.tile.get();
        std::shared_ptr<const detail::Tile> t = tile(root);
        slot.root = root;
        slot.tile = std::move(t);
        return slot.tile.get();
    }

    std::shared_ptr<const detail::Tile> tile(const NodeId& root) {
        std::shared_ptr<const detail::Tile> t;
        if (!tiles.lookup(root, t)) t = build(root);
        return t;
    }

    std::shared_ptr<const detail::Tile> build(const NodeId& root) {
        // A child tile starts from its parent tile's last patch (rebuilt in
        // turn if it was evicted: values never depend on the cache).
        std::shared_ptr<const detail::Tile> parent;
        if (root.level > 0) parent = tile(detail::parent_tile_root(root));
        auto built = std::make_shared<const detail::Tile>(context, root,
                                                          parent ? &parent->last_patch() : nullptr);
        tiles.insert(root, built, built->bytes_when_complete());
        return built;
    }

    /// Never reused, so a thread's front cannot confuse two hierarchies.
    const std::uint64_t id = g_next_hierarchy_id.fetch_add(1);

    std::atomic<std::uint64_t> nodes_built{0};
    detail::BaseTopology topo;
    detail::TileContext context;
    detail::RootRecords roots;
    detail::ShardedLruCache<NodeId, std::shared_ptr<const detail::Tile>, NodeKeyHash> tiles;
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
    c.bytes = t.bytes + impl_->roots.owned_bytes();
    c.peak_bytes = t.peak_bytes + impl_->roots.owned_bytes();
    return c;
}

}  // namespace subdivtrace

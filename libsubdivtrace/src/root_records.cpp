// The base level's records, built in chunks on one thread per core (root_records.h).
#include "root_records.h"

#include <algorithm>

#include "huge_pages.h"
#include "parallel.h"
#include "patch_records.h"

namespace subdivtrace::detail {

namespace {

/// Base triangles whose level-0 records are computed from one patch.
constexpr std::size_t k_root_chunk = 4096;

}  // namespace

RootRecords::RootRecords(const TileContext& ctx) : mesh_(&ctx.topo.mesh()) {
    const std::size_t face_count = ctx.topo.face_count();
    const std::size_t vertex_count = mesh_->positions.size();
    // On huge pages (huge_pages.h): a 1M-triangle mesh's arrays faulted
    // 4 kB pages by the ten thousand, about 10 us each here.
    detail::resize_huge(normal_, vertex_count);
    detail::resize_huge(shading_, vertex_count);
    detail::resize_huge(displacement_, vertex_count);
    detail::resize_huge(edge_normal_, 3 * face_count);
    if (ctx.scheme.draws_limit_points()) detail::resize_huge(draw_, vertex_count);
    detail::resize_huge(shells_, face_count);

    // A vertex keeps the values of its first corner, the one in its lowest
    // face (the first of topo.faces_of_vertex); the corners whose normals
    // differ (across a crease) are kept apart. Knowing that face up front
    // lets the chunks below run on several threads: each per-vertex value
    // has exactly one writer.
    // In chunks of base triangles, each with the border its records read:
    // the whole mesh at once made the base level's patch most of a large
    // mesh's construction peak.
    const std::size_t chunk_count = (face_count + k_root_chunk - 1) / k_root_chunk;
    std::vector<ChunkCorners> corners(chunk_count);
    run_in_parallel<BasePatchScratch>(chunk_count, [&](std::size_t chunk, BasePatchScratch& scratch) {
        build_chunk(ctx, chunk * k_root_chunk, std::min(face_count, (chunk + 1) * k_root_chunk),
                    scratch, corners[chunk]);
    });
    // The corners a chunk could not compare (their vertex's first corner is
    // in an earlier chunk) are compared now; chunks and their lists are in
    // slot order, so split_corners_ ascends.
    for (ChunkCorners& chunk : corners) {
        std::vector<SplitCorner> merged;
        merged.reserve(chunk.split.size() + chunk.deferred.size());
        auto split = chunk.split.begin();
        for (const SplitCorner& d : chunk.deferred) {
            for (; split != chunk.split.end() && split->slot < d.slot; ++split) merged.push_back(*split);
            const std::uint32_t v = mesh_->triangles[d.slot / 3][d.slot % 3];
            if (d.normal != normal_[v] || d.shading != shading_[v]) merged.push_back(d);
        }
        merged.insert(merged.end(), split, chunk.split.end());
        split_corners_.insert(split_corners_.end(), merged.begin(), merged.end());
    }
    split_corners_.shrink_to_fit();
    linear_shading_ = !corners.empty() && corners.front().linear_shading;
    ctx.records_built->fetch_add(shells_.size(), std::memory_order_relaxed);
}

void RootRecords::build_chunk(const TileContext& ctx, std::size_t first, std::size_t last,
                              BasePatchScratch& scratch, ChunkCorners& out) {
    std::vector<std::uint32_t> region;
    for (std::size_t f = first; f < last; ++f) region.push_back(static_cast<std::uint32_t>(f));
    Patch p = base_patch(ctx.topo, region.data(), region.size(), &scratch);
    p.finish(ctx.topo, ctx.scheme);
    // The next level's positions only: the shells read its edge points
    // (and Loop's moved corners), never its triangles.
    Flags in_chunk(p.tris.size());
    for (std::size_t t = 0; t < p.tris.size(); ++t)
        in_chunk[t] = p.tris[t].id.face >= first && p.tris[t].id.face < last;
    const Flags needed = p.points_around(in_chunk);
    Patch next;
    p.next_positions(ctx.topo, ctx.scheme, &needed, next);
    ShadingMemo memo(p);
    // The patch's triangles ascend by face, so its corners by slot.
    for (std::uint32_t t = 0; t < p.tris.size(); ++t) {
        if (!in_chunk[t]) continue;  // border
        const std::uint32_t f = p.tris[t].id.face;
        for (std::uint32_t v : p.tris[t].v) p.ensure_normal(ctx.topo, ctx.scheme, v);
        const NodeRecord rec = make_record(ctx, p, &next, t, memo);
        shells_[f] = CompactShell::from(rec.shell, rec.position[0]);
        out.linear_shading = rec.linear_shading;  // the same for every level-0 record
        for (int e = 0; e < 3; ++e) edge_normal_[3 * f + e] = rec.edge_normal[e];
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t v = p.verts[p.tris[t].v[c]].key.a;
            const std::uint32_t slot = 3 * f + static_cast<std::uint32_t>(c);
            const SplitCorner corner{slot, p.corner_normal[3 * t + c], glm::vec3(rec.shading_normal[c])};
            const std::uint32_t first_face = ctx.topo.faces_of_vertex(v)[0];
            if (f == first_face) {
                normal_[v] = corner.normal;
                shading_[v] = corner.shading;
                displacement_[v] = rec.displacement[c];
                if (!draw_.empty()) draw_[v] = rec.draw_position[c];
            } else if (first_face < first) {
                // Written by an earlier chunk. A vertex with one sector has
                // the same normals at every corner (one sum over its whole
                // ring, in canonical order), so only crease vertices wait:
                // keeping every such corner cost 17 MB at 943k triangles.
                if (!p.derived[p.tris[t].v[c]].single_sector) out.deferred.push_back(corner);
            } else if (corner.normal != normal_[v] || corner.shading != shading_[v]) {
                out.split.push_back(corner);
            }
        }
    }
}

std::pair<const RootRecords::SplitCorner*, const RootRecords::SplitCorner*> RootRecords::splits_of(
    std::uint32_t face) const {
    const SplitCorner* begin = split_corners_.data();
    const SplitCorner* end = begin + split_corners_.size();
    const auto below = [](const SplitCorner& x, std::uint32_t slot) { return x.slot < slot; };
    const SplitCorner* lo = std::lower_bound(begin, end, 3 * face, below);
    return {lo, std::lower_bound(lo, end, 3 * face + 3, below)};
}

Vec3 RootRecords::corner_normal(std::uint32_t face, int c) const {
    const auto [lo, hi] = splits_of(face);
    for (const SplitCorner* it = lo; it != hi; ++it)
        if (it->slot == 3 * face + static_cast<std::uint32_t>(c)) return it->normal;
    return normal_[mesh_->triangles[face][c]];
}

void RootRecords::lend_normals(Patch& p) const {
    // A level-0 patch triangle is its base triangle, corners in the same order.
    for (std::uint32_t v = 0; v < p.verts.size(); ++v)
        p.adopt_normal(v, [&](std::uint32_t slot) {
            return corner_normal(p.tris[slot / 3].id.face, static_cast<int>(slot % 3));
        });
}

NodeRecord RootRecords::record(std::uint32_t face, bool normals, bool with_shell) const {
    NodeRecord rec;
    const Triangle& t = mesh_->triangles[face];
    for (int c = 0; c < 3; ++c) {
        rec.position[c] = mesh_->positions[t[c]];
        rec.displacement[c] = displacement_[t[c]];
        rec.draw_position[c] = draw_.empty() ? rec.position[c] : draw_[t[c]];
        if (normals) {
            rec.shading_normal[c] = Vec3(shading_[t[c]]);
            rec.edge_normal[c] = edge_normal_[3 * std::size_t{face} + c];
        }
    }
    rec.linear_shading = linear_shading_;
    if (normals && !split_corners_.empty()) {
        const auto [lo, hi] = splits_of(face);
        for (const SplitCorner* it = lo; it != hi; ++it) {
            rec.shading_normal[it->slot - 3 * face] = Vec3(it->shading);
        }
    }
    if (with_shell) rec.shell = shell(face);
    return rec;
}

std::size_t RootRecords::owned_bytes() const {
    return (normal_.capacity() + draw_.capacity()) * sizeof(Vec3) +
           (shading_.capacity() + edge_normal_.capacity()) * sizeof(glm::vec3) +
           displacement_.capacity() * sizeof(float) +
           shells_.capacity() * sizeof(CompactShell) + split_corners_.capacity() * sizeof(SplitCorner);
}

}  // namespace subdivtrace::detail

#pragma once
// Base triangles grouped into small connected chunks, so that the level
// their tiles start from is computed once per chunk (tile.h, chunk_level):
// a lone base triangle's tile would subdivide a border many times its own
// size, and a chunk of neighbours shares one.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "base_topology.h"

namespace subdivtrace::detail {

/// Base triangles per chunk (at most). Measured on small objects in
/// docs/benchmarks.md ("Root tiles by chunks").
constexpr std::size_t k_face_chunk_size = 16;

/// A partition of the base faces into chunks of at most `max_size` faces,
/// each grown breadth-first from its lowest face over faces that share a
/// vertex, so a chunk is a compact, connected patch of the surface.
class FaceChunks {
public:
    FaceChunks(const BaseTopology& topo, std::size_t max_size);

    /// The chunk that holds `face`, in [0, chunk_count()).
    std::uint32_t chunk_index(std::uint32_t face) const { return chunk_[face]; }
    /// The faces in the chunk of `face` (ascending, `face` among them).
    std::pair<const std::uint32_t*, const std::uint32_t*> chunk_of(std::uint32_t face) const {
        const std::uint32_t c = chunk_[face];
        return {members_.data() + offsets_[c], members_.data() + offsets_[c + 1]};
    }
    std::size_t chunk_count() const { return offsets_.empty() ? 0 : offsets_.size() - 1; }
    std::size_t owned_bytes() const {
        return (chunk_.capacity() + members_.capacity() + offsets_.capacity()) * sizeof(std::uint32_t);
    }

private:
    std::vector<std::uint32_t> chunk_;    ///< per face
    std::vector<std::uint32_t> members_;  ///< faces by chunk
    std::vector<std::uint32_t> offsets_;  ///< chunk c's faces: members_[offsets_[c], offsets_[c + 1])
};

}  // namespace subdivtrace::detail

#include "face_chunks.h"

#include <algorithm>

namespace subdivtrace::detail {

FaceChunks::FaceChunks(const BaseTopology& topo, std::size_t max_size) {
    constexpr std::uint32_t k_unassigned = UINT32_MAX;
    const std::size_t face_count = topo.face_count();
    const auto& triangles = topo.mesh().triangles;
    chunk_.assign(face_count, k_unassigned);
    members_.reserve(face_count);
    offsets_.push_back(0);
    max_size = std::max<std::size_t>(max_size, 1);
    for (std::uint32_t seed = 0; seed < face_count; ++seed) {
        if (chunk_[seed] != k_unassigned) continue;
        const auto c = static_cast<std::uint32_t>(offsets_.size() - 1);
        const std::size_t first = members_.size();
        chunk_[seed] = c;
        members_.push_back(seed);
        // Breadth-first: the members themselves are the queue.
        for (std::size_t next = first; next < members_.size(); ++next) {
            for (std::uint32_t v : triangles[members_[next]]) {
                for (std::uint32_t f : topo.faces_of_vertex(v)) {
                    if (members_.size() - first >= max_size) break;
                    if (chunk_[f] != k_unassigned) continue;
                    chunk_[f] = c;
                    members_.push_back(f);
                }
            }
        }
        std::sort(members_.begin() + static_cast<std::ptrdiff_t>(first), members_.end());
        offsets_.push_back(static_cast<std::uint32_t>(members_.size()));
    }
}

}  // namespace subdivtrace::detail

#pragma once
// A map from 32-bit ids to 32-bit values, sized to what it holds rather than
// to the largest id: linear-probing slots in a power-of-two array that
// doubles at half load. For deduplicating the few hundred vertex and face ids
// of a small region in linear time (base_patch), where sorting them was most
// of the work and stamps sized to the mesh cost memory per thread.

#include <cstdint>
#include <vector>

namespace subdivtrace::detail {

class IdTable {
public:
    /// Empties the table, keeping its slots for reuse.
    void clear() {
        slots_.assign(slots_.empty() ? 64 : slots_.size(), Slot{});
        size_ = 0;
    }

    /// Inserts `id` with `value` if it is absent: true if it was.
    bool insert(std::uint32_t id, std::uint32_t value = 0) {
        if (2 * (size_ + 1) > slots_.size()) grow();
        Slot& s = find(id);
        if (s.used) return false;
        s = {id, value, true};
        ++size_;
        return true;
    }

    /// The value of `id`, which must be present.
    std::uint32_t at(std::uint32_t id) { return find(id).value; }

private:
    struct Slot {
        std::uint32_t id = 0;
        std::uint32_t value = 0;
        bool used = false;
    };

    Slot& find(std::uint32_t id) {
        const std::size_t mask = slots_.size() - 1;
        std::size_t h = (id * 0x9E3779B1u) & mask;
        while (slots_[h].used && slots_[h].id != id) h = (h + 1) & mask;
        return slots_[h];
    }

    void grow() {
        std::vector<Slot> old(slots_.empty() ? 64 : 2 * slots_.size());
        old.swap(slots_);
        for (const Slot& s : old)
            if (s.used) find(s.id) = s;
    }

    std::vector<Slot> slots_;
    std::size_t size_ = 0;
};

}  // namespace subdivtrace::detail

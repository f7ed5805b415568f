#pragma once
// Welding coincident vertices (mesh.h, WeldOptions): the one place where the
// positions of every input (files, POV-Ray arrays) become the topology's vertices.

#include <cstdint>
#include <vector>

#include "subdivtrace/mesh.h"

namespace subdivtrace {

/// Where each input vertex went.
struct WeldMap {
    /// remap[i] = index of input vertex i among `positions`.
    std::vector<std::uint32_t> remap;
    /// The representatives, in order of first appearance; each keeps the
    /// position of its first occurrence (exactly, never averaged).
    std::vector<Vec3> positions;
};

/// Welds `positions`: exact mode (tolerance <= 0) joins bit-identical
/// coordinates (-0 equals +0); with tolerance > 0 a vertex joins the first
/// earlier representative within that distance (not transitively, so a chain
/// of close points does not collapse into one). Linear expected time; memory
/// 8 bytes per vertex for the table plus the output.
WeldMap weld_positions(const std::vector<Vec3>& positions, double tolerance);

}  // namespace subdivtrace

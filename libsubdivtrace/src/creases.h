#pragma once
// Creases from split normals (docs/schemes.md, "Creases and boundaries"): an
// edge between two triangles whose corners at either endpoint carry different
// given normals is a crease, like a hard edge in the program that wrote the
// mesh. Shared by uniform subdivision and the lazy hierarchy.

#include <cstdint>
#include <vector>

#include "edge_sides.h"
#include "subdivtrace/mesh.h"
#include "subdivtrace/scheme.h"
#include "subdivtrace/uniform.h"

namespace subdivtrace::detail {

/// Per triangle, bit e set when its edge e (corner e to corner e + 1) is a
/// crease. All zero for a mesh without normals. Edges with one triangle are
/// boundaries, not creases; edges with three or more are never creases.
std::vector<std::uint8_t> crease_masks(const Mesh& mesh);
/// The same from the mesh's sides (sorted_edge_sides), for a caller that has them.
std::vector<std::uint8_t> crease_masks(const Mesh& mesh, const HugeArray<EdgeSide>& sides);

/// The normal the mesh gives at base vertex `v` in triangle `face`
/// (normalised; zero if the mesh gives none or v is not a corner of face).
Vec3 given_normal_of(const Mesh& mesh, std::uint32_t face, std::uint32_t v);

/// Whether base vertices keep their given normals at every level of the
/// normal scheme (true), or only at level 0 with Gouraud normals from level 1
/// on. docs/schemes.md, "Given normals", has the measurement behind the choice.
constexpr bool k_given_normals_every_level = false;

/// subdivide_uniform with either rule for given normals (the measurement in
/// docs/schemes.md compares them; the library uses k_given_normals_every_level).
SubdividedMesh subdivide_uniform(const Mesh& mesh, SchemeKind scheme, int levels,
                                 bool given_every_level);

/// What lies beyond endpoint v of a curve edge (v, other) for the curve
/// rules (docs/schemes.md, "Creases and boundaries"), from v's curve edges
/// (`curve_count` of them, to `curve_nbr[0]` and `curve_nbr[1]`): the
/// curve's next vertex where v has two curve edges, `other` one of them
/// (the curve goes on); a dart's sector normal where v has one curve edge
/// ending inside one smooth sector; else nothing (a corner of the curve).
/// One rule for uniform levels and tiles.
struct CurveEnd {
    bool has_far = false;
    std::uint32_t far = 0;  ///< the curve's next vertex, when has_far
    bool dart = false;      ///< take v's one sector's normal
};
inline CurveEnd curve_end(int curve_count, const std::uint32_t* curve_nbr, std::uint32_t other,
                          bool single_sector) {
    CurveEnd end;
    if (curve_count == 2 && (curve_nbr[0] == other || curve_nbr[1] == other)) {
        end.has_far = true;
        end.far = curve_nbr[0] == other ? curve_nbr[1] : curve_nbr[0];
    } else {
        end.dart = curve_count == 1 && single_sector;
    }
    return end;
}

/// Two given normals belong to different sides of a crease: their angle
/// exceeds about 0.01 degrees (exporters round normals far below that).
bool normals_split(const Vec3& n1, const Vec3& n2);

/// Groups the triangles around one vertex into sectors: two of them share a
/// sector when they meet along an edge at the vertex that is not a crease.
/// Corner k of the fan has the edges `prev` and `next` at the centre (any id
/// that names an edge the same way for every triangle on it) and
/// `crease_prev` / `crease_next` for them. Writes a label per corner
/// (0 .. count-1, in first-seen order) and returns the number of sectors.
struct FanCorner {
    std::uint32_t prev = 0;
    std::uint32_t next = 0;
    bool crease_prev = false;
    bool crease_next = false;
};
std::uint32_t label_sectors(const std::vector<FanCorner>& corners, std::vector<std::uint32_t>& labels);

/// Butterfly's view of a vertex that creases split into sectors: the sector
/// of `ring` that holds neighbour `index`, as an open fan from the curve edge
/// before it to the curve edge after it (a crease is a boundary to each side,
/// as Zorin et al. treat it); `index` is renumbered within it. `curve[k]`
/// flags neighbour k's edge as a curve edge. Irregular rings stay as they are.
void restrict_to_sector(VertexRing& ring, const std::uint8_t* curve, std::size_t& index);

}  // namespace subdivtrace::detail

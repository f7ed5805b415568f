// OpenMesh's VectorT leaves its default-constructed coordinates uninitialised on
// purpose; GCC 12 then warns inside <vector> when OpenMesh appends a property.
// The state at the warning's location counts, so this must precede every include.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include "unit/test_meshes.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <stdexcept>
#include <unordered_map>
#include <utility>

#include <glm/geometric.hpp>

namespace subdivtrace::testmesh {

namespace {

constexpr double k_pi = 3.14159265358979323846;

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
    if (a > b) std::swap(a, b);
    return (static_cast<std::uint64_t>(a) << 32) | b;
}

Vec3 face_normal(const std::vector<Vec3>& p, const Triangle& t) {
    return glm::cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]);
}

/// Cosine between a face's normal and the direction of its centroid from the
/// origin: 1 for a face looking straight out of a sphere around the origin.
double outward_cosine(const std::vector<Vec3>& p, const Triangle& t) {
    const Vec3 n = face_normal(p, t);
    const Vec3 c = p[t[0]] + p[t[1]] + p[t[2]];
    const double len = glm::length(n) * glm::length(c);
    return len > 0.0 ? glm::dot(n, c) / len : -1.0;
}

/// Edge flips on a closed triangle list, keeping valences in [3, 12], the mesh
/// manifold, and every face facing away from the origin (so the flipped mesh of
/// points on a sphere stays embedded).
class Flipper {
public:
    Flipper(std::vector<Vec3>& positions, std::vector<Triangle>& triangles)
        : p_(positions), t_(triangles), incident_(positions.size(), 0) {
        for (const Triangle& t : t_)
            for (std::uint32_t v : t) ++incident_[v];
        for (std::uint32_t f = 0; f < t_.size(); ++f)
            for (int i = 0; i < 3; ++i) add_edge(f, i);
    }

    int valence(std::uint32_t v) const { return incident_[v]; }

    /// Flips the edge from corner i to corner i + 1 of face f, if allowed.
    bool flip(std::uint32_t f1, int i) {
        const std::uint32_t a = t_[f1][i], b = t_[f1][(i + 1) % 3], c = t_[f1][(i + 2) % 3];
        const auto it = directed_.find(directed_key(b, a));
        if (it == directed_.end()) return false;
        const std::uint32_t f2 = it->second;
        const Triangle& t2 = t_[f2];
        const int j = t2[0] == b ? 0 : (t2[1] == b ? 1 : 2);
        const std::uint32_t d = t2[(j + 2) % 3];
        if (c == d || incident_[a] <= 3 || incident_[b] <= 3) return false;
        if (incident_[c] >= 12 || incident_[d] >= 12) return false;
        if (directed_.count(directed_key(c, d)) || directed_.count(directed_key(d, c)))
            return false;
        const Triangle n1{c, a, d};
        const Triangle n2{d, b, c};
        if (outward_cosine(p_, n1) < 0.25 || outward_cosine(p_, n2) < 0.25) return false;

        for (int k = 0; k < 3; ++k) {
            remove_edge(f1, k);
            remove_edge(f2, k);
        }
        t_[f1] = n1;
        t_[f2] = n2;
        for (int k = 0; k < 3; ++k) {
            add_edge(f1, k);
            add_edge(f2, k);
        }
        --incident_[a];
        --incident_[b];
        ++incident_[c];
        ++incident_[d];
        return true;
    }

    /// Faces around v (any order).
    std::vector<std::pair<std::uint32_t, int>> corners_of(std::uint32_t v) const {
        std::vector<std::pair<std::uint32_t, int>> out;
        for (std::uint32_t f = 0; f < t_.size(); ++f)
            for (int i = 0; i < 3; ++i)
                if (t_[f][i] == v) out.emplace_back(f, i);
        return out;
    }

private:
    static std::uint64_t directed_key(std::uint32_t a, std::uint32_t b) {
        return (static_cast<std::uint64_t>(a) << 32) | b;
    }
    void add_edge(std::uint32_t f, int i) {
        directed_[directed_key(t_[f][i], t_[f][(i + 1) % 3])] = f;
    }
    void remove_edge(std::uint32_t f, int i) {
        directed_.erase(directed_key(t_[f][i], t_[f][(i + 1) % 3]));
    }

    std::vector<Vec3>& p_;
    std::vector<Triangle>& t_;
    std::vector<int> incident_;
    std::unordered_map<std::uint64_t, std::uint32_t> directed_;
};

}  // namespace

namespace {

/// Splits every triangle 1-to-4 `times` times, projecting each new point
/// onto the unit sphere (children in uniform.h's order).
void split_onto_sphere(Mesh& m, int times) {
    for (int level = 0; level < times; ++level) {
        std::map<std::uint64_t, std::uint32_t> mid;
        auto midpoint = [&](std::uint32_t u, std::uint32_t w) {
            const auto [it, inserted] =
                mid.emplace(edge_key(u, w), static_cast<std::uint32_t>(m.positions.size()));
            if (inserted) m.positions.push_back(glm::normalize(m.positions[u] + m.positions[w]));
            return it->second;
        };
        std::vector<Triangle> next;
        next.reserve(4 * m.triangles.size());
        for (const Triangle& t : m.triangles) {
            const std::uint32_t ab = midpoint(t[0], t[1]);
            const std::uint32_t bc = midpoint(t[1], t[2]);
            const std::uint32_t ca = midpoint(t[2], t[0]);
            next.push_back({t[0], ab, ca});
            next.push_back({ab, t[1], bc});
            next.push_back({ca, bc, t[2]});
            next.push_back({ab, bc, ca});
        }
        m.triangles.swap(next);
    }
}

}  // namespace

Mesh icosphere(int subdivisions) {
    Mesh m = icosahedron();
    split_onto_sphere(m, subdivisions);
    return m;
}

Mesh torus(int rings, int sides, double R, double r) {
    Mesh m;
    for (int i = 0; i < rings; ++i) {
        const double u = 2.0 * k_pi * i / rings;
        for (int j = 0; j < sides; ++j) {
            const double v = 2.0 * k_pi * j / sides;
            const double w = R + r * std::cos(v);
            m.positions.push_back({w * std::cos(u), w * std::sin(u), r * std::sin(v)});
        }
    }
    auto id = [&](int i, int j) {
        return static_cast<std::uint32_t>((i % rings) * sides + (j % sides));
    };
    for (int i = 0; i < rings; ++i) {
        for (int j = 0; j < sides; ++j) {
            // (i, j) -> (i+1, j) runs along u, (i, j) -> (i, j+1) along v; u x v
            // points out of the tube.
            m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    }
    return m;
}

Mesh irregular_closed(unsigned seed) {
    Mesh m = icosphere(2);
    std::mt19937 rng(seed);
    Flipper flipper(m.positions, m.triangles);
    const auto face_count = static_cast<std::uint32_t>(m.triangles.size());
    const auto vertex_count = static_cast<std::uint32_t>(m.positions.size());

    // Random flips spread the valences.
    std::uniform_int_distribution<std::uint32_t> pick_face(0, face_count - 1);
    std::uniform_int_distribution<int> pick_corner(0, 2);
    for (int attempt = 0; attempt < 3000; ++attempt) flipper.flip(pick_face(rng), pick_corner(rng));

    // Raise one vertex to valence 12: flip the edges opposite it in its fan.
    std::uniform_int_distribution<std::uint32_t> pick_vertex(0, vertex_count - 1);
    const std::uint32_t hub = pick_vertex(rng);
    for (int round = 0; round < 50 && flipper.valence(hub) < 12; ++round) {
        for (const auto& [f, i] : flipper.corners_of(hub)) {
            if (flipper.valence(hub) >= 12) break;
            flipper.flip(f, (i + 1) % 3);
        }
    }
    // Lower another vertex, far from the hub, to valence 3: flip its own edges.
    std::uint32_t low = 0;
    for (std::uint32_t v = 0; v < vertex_count; ++v) {
        if (glm::dot(m.positions[v], m.positions[hub]) < glm::dot(m.positions[low], m.positions[hub]))
            low = v;
    }
    for (int round = 0; round < 50 && flipper.valence(low) > 3; ++round) {
        for (const auto& [f, i] : flipper.corners_of(low)) {
            if (flipper.valence(low) <= 3) break;
            flipper.flip(f, i);
        }
    }

    // Perturb radially: keeps the faces facing outward, breaks all symmetry.
    std::uniform_real_distribution<double> radial(0.97, 1.03);
    for (Vec3& p : m.positions) p *= radial(rng);
    return m;
}

Mesh open_grid(int n) {
    Mesh m;
    for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i) {
            const double x = -1.0 + 2.0 * i / n;
            const double y = -1.0 + 2.0 * j / n;
            const double z = 0.2 * std::sin(k_pi * x) * std::cos(0.5 * k_pi * y) + 0.1 * x * y;
            m.positions.push_back({x, y, z});
        }
    }
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const std::uint32_t v00 = grid_index(n, i, j), v10 = grid_index(n, i + 1, j);
            const std::uint32_t v01 = grid_index(n, i, j + 1), v11 = grid_index(n, i + 1, j + 1);
            if ((i + j) % 2 == 0) {
                m.triangles.push_back({v00, v10, v11});
                m.triangles.push_back({v00, v11, v01});
            } else {
                m.triangles.push_back({v00, v10, v01});
                m.triangles.push_back({v10, v11, v01});
            }
        }
    }
    return m;
}

Mesh faceted_cube() {
    Mesh m;
    for (int k = 0; k < 8; ++k) m.positions.push_back(Vec3(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1));
    // Each face as two triangles, counter-clockwise from outside, with its normal.
    const struct {
        std::uint32_t q[4];
        Vec3 normal;
    } faces[6] = {
        {{0, 2, 3, 1}, Vec3(0, 0, -1)}, {{4, 5, 7, 6}, Vec3(0, 0, 1)},
        {{0, 1, 5, 4}, Vec3(0, -1, 0)}, {{2, 6, 7, 3}, Vec3(0, 1, 0)},
        {{0, 4, 6, 2}, Vec3(-1, 0, 0)}, {{1, 3, 7, 5}, Vec3(1, 0, 0)},
    };
    for (const auto& f : faces) {
        for (const Triangle& t : {Triangle{f.q[0], f.q[1], f.q[2]}, Triangle{f.q[0], f.q[2], f.q[3]}}) {
            m.triangles.push_back(t);
            for (int c = 0; c < 3; ++c) m.corner_normals.push_back(f.normal);
        }
    }
    return m;
}

Mesh split_normal_cylinder(int n, double r, double h) {
    Mesh m;
    // Rim vertices: bottom 0..n-1, top n..2n-1; cap centres 2n (bottom), 2n+1 (top).
    for (int z = 0; z < 2; ++z)
        for (int i = 0; i < n; ++i) {
            const double a = 2.0 * k_pi * i / n;
            m.positions.push_back(Vec3(r * std::cos(a), r * std::sin(a), z ? h : -h));
        }
    m.positions.push_back(Vec3(0, 0, -h));
    m.positions.push_back(Vec3(0, 0, h));
    const auto radial = [&](std::uint32_t v) {
        const Vec3& p = m.positions[v];
        return glm::normalize(Vec3(p.x, p.y, 0.0));
    };
    const auto n32 = static_cast<std::uint32_t>(n);
    for (std::uint32_t i = 0; i < n32; ++i) {
        const std::uint32_t j = (i + 1) % n32;
        for (const Triangle& t : {Triangle{i, j, n32 + j}, Triangle{i, n32 + j, n32 + i}}) {
            m.triangles.push_back(t);
            for (std::uint32_t v : t) m.corner_normals.push_back(radial(v));
        }
        m.triangles.push_back({2 * n32, j, i});
        for (int c = 0; c < 3; ++c) m.corner_normals.push_back(Vec3(0, 0, -1));
        m.triangles.push_back({2 * n32 + 1, n32 + i, n32 + j});
        for (int c = 0; c < 3; ++c) m.corner_normals.push_back(Vec3(0, 0, 1));
    }
    return m;
}

Mesh icosphere_with_normals(int subdivisions) {
    Mesh m = icosphere(subdivisions);
    for (const Triangle& t : m.triangles)
        for (std::uint32_t v : t) m.corner_normals.push_back(glm::normalize(m.positions[v]));
    return m;
}

Mesh octasphere_half(int subdivisions, bool upper) {
    Mesh m;
    m.positions = {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1), Vec3(0, 0, -1)};
    m.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    split_onto_sphere(m, subdivisions);
    // Keep one half; renumber its vertices in order of first use.
    Mesh half;
    std::vector<std::uint32_t> remap(m.positions.size(), UINT32_MAX);
    for (const Triangle& t : m.triangles) {
        const double z = m.positions[t[0]].z + m.positions[t[1]].z + m.positions[t[2]].z;
        if ((z > 0.0) != upper) continue;
        Triangle out;
        for (int c = 0; c < 3; ++c) {
            if (remap[t[c]] == UINT32_MAX) {
                remap[t[c]] = static_cast<std::uint32_t>(half.positions.size());
                half.positions.push_back(m.positions[t[c]]);
            }
            out[c] = remap[t[c]];
        }
        half.triangles.push_back(out);
    }
    return half;
}

double max_aspect_ratio(const Mesh& mesh) {
    double worst = 0.0;
    for (const Triangle& t : mesh.triangles) {
        const Vec3& a = mesh.positions[t[0]];
        const Vec3& b = mesh.positions[t[1]];
        const Vec3& c = mesh.positions[t[2]];
        const double longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
        const double area2 = glm::length(glm::cross(b - a, c - a));
        worst = std::max(worst, area2 > 0.0 ? longest * longest / area2
                                            : std::numeric_limits<double>::infinity());
    }
    return worst;
}

std::vector<int> valences(const Mesh& mesh) {
    std::vector<std::vector<std::uint32_t>> nbrs(mesh.positions.size());
    for (const Triangle& t : mesh.triangles) {
        for (int i = 0; i < 3; ++i) {
            nbrs[t[i]].push_back(t[(i + 1) % 3]);
            nbrs[t[i]].push_back(t[(i + 2) % 3]);
        }
    }
    std::vector<int> out(mesh.positions.size());
    for (std::size_t v = 0; v < nbrs.size(); ++v) {
        std::sort(nbrs[v].begin(), nbrs[v].end());
        out[v] = static_cast<int>(std::unique(nbrs[v].begin(), nbrs[v].end()) - nbrs[v].begin());
    }
    return out;
}

Triangle canonical(Triangle t) {
    const auto first = std::min_element(t.begin(), t.end()) - t.begin();
    std::rotate(t.begin(), t.begin() + first, t.end());
    return t;
}

double bbox_diagonal(const std::vector<Vec3>& positions) {
    if (positions.empty()) return 0.0;
    Vec3 lo = positions[0], hi = positions[0];
    for (const Vec3& p : positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    return glm::length(hi - lo);
}

std::vector<std::uint32_t> match_positions(const std::vector<Vec3>& a,
                                           const std::vector<Vec3>& b, double cell,
                                           double* max_distance) {
    struct KeyHash {
        std::size_t operator()(const std::array<long long, 3>& k) const {
            std::size_t h = 1469598103934665603ull;
            for (long long x : k) h = (h ^ static_cast<std::size_t>(x)) * 1099511628211ull;
            return h;
        }
    };
    auto key = [cell](const Vec3& p) {
        return std::array<long long, 3>{static_cast<long long>(std::floor(p.x / cell)),
                                        static_cast<long long>(std::floor(p.y / cell)),
                                        static_cast<long long>(std::floor(p.z / cell))};
    };
    std::unordered_map<std::array<long long, 3>, std::vector<std::uint32_t>, KeyHash> grid;
    for (std::uint32_t i = 0; i < b.size(); ++i) grid[key(b[i])].push_back(i);

    std::vector<std::uint32_t> out(a.size(), UINT32_MAX);
    double worst = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const auto k = key(a[i]);
        double best = std::numeric_limits<double>::infinity();
        for (long long dx = -1; dx <= 1; ++dx) {
            for (long long dy = -1; dy <= 1; ++dy) {
                for (long long dz = -1; dz <= 1; ++dz) {
                    const auto it = grid.find({k[0] + dx, k[1] + dy, k[2] + dz});
                    if (it == grid.end()) continue;
                    for (std::uint32_t j : it->second) {
                        const double dist = glm::length(a[i] - b[j]);
                        if (dist < best) {
                            best = dist;
                            out[i] = j;
                        }
                    }
                }
            }
        }
        if (out[i] != UINT32_MAX) worst = std::max(worst, best);
    }
    if (max_distance) *max_distance = worst;
    return out;
}

OmMesh to_openmesh(const Mesh& mesh) {
    OmMesh om;
    std::vector<OmMesh::VertexHandle> handles;
    handles.reserve(mesh.positions.size());
    for (const Vec3& p : mesh.positions) handles.push_back(om.add_vertex({p.x, p.y, p.z}));
    for (const Triangle& t : mesh.triangles) {
        const OmMesh::FaceHandle f = om.add_face(handles[t[0]], handles[t[1]], handles[t[2]]);
        if (!f.is_valid()) throw std::runtime_error("to_openmesh: OpenMesh refused a face");
    }
    return om;
}

Mesh from_openmesh(const OmMesh& om) {
    Mesh m;
    m.positions.reserve(om.n_vertices());
    for (const auto v : om.vertices()) {
        const OpenMesh::Vec3d& p = om.point(v);
        m.positions.push_back({p[0], p[1], p[2]});
    }
    for (const auto f : om.faces()) {
        Triangle t{};
        int i = 0;
        for (const auto v : om.fv_range(f)) {
            if (i < 3) t[i] = static_cast<std::uint32_t>(v.idx());
            ++i;
        }
        if (i != 3) throw std::runtime_error("from_openmesh: a face is not a triangle");
        m.triangles.push_back(t);
    }
    return m;
}

MeshArrays patch_split_sphere(int n, bool shared) {
    // Each cube face: the axis it is normal to, its side, and the (u, v) axes
    // with u x v = the outward normal, so (u, v)-counter-clockwise is outward.
    struct Face {
        int axis, u, v;
        bool positive;
    };
    static const Face faces[6] = {{0, 1, 2, true},  {0, 2, 1, false}, {1, 2, 0, true},
                                  {1, 0, 2, false}, {2, 0, 1, true},  {2, 1, 0, false}};
    MeshArrays out;
    std::map<std::array<int, 3>, std::int64_t> lattice_index;  // shared only
    for (const Face& f : faces) {
        // The patch's vertices, j-major, and where each one went.
        std::vector<std::int64_t> index((n + 1) * (n + 1));
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) {
                std::array<int, 3> c{};
                c[f.axis] = f.positive ? n : 0;
                c[f.u] = i;
                c[f.v] = j;
                const Vec3 cube(2.0 * c[0] / n - 1.0, 2.0 * c[1] / n - 1.0, 2.0 * c[2] / n - 1.0);
                const Vec2 uv(double(i) / n, double(j) / n);
                std::int64_t& slot = index[j * (n + 1) + i];
                if (shared) {
                    auto [it, inserted] = lattice_index.emplace(
                        c, static_cast<std::int64_t>(out.positions.size()));
                    if (inserted) out.positions.push_back(glm::normalize(cube));
                    slot = it->second;
                    out.uvs.push_back(uv);
                } else {
                    slot = static_cast<std::int64_t>(out.positions.size());
                    out.positions.push_back(glm::normalize(cube));
                    out.uvs.push_back(uv);
                }
            }
        // UVs are numbered per patch vertex in both versions.
        const std::int64_t uv_base = static_cast<std::int64_t>(out.uvs.size()) - (n + 1) * (n + 1);
        auto at = [&](int i, int j) { return index[j * (n + 1) + i]; };
        auto uv_at = [&](int i, int j) { return uv_base + j * (n + 1) + i; };
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                out.face_indices.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
                out.face_indices.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
                if (shared) {
                    out.uv_indices.push_back({uv_at(i, j), uv_at(i + 1, j), uv_at(i + 1, j + 1)});
                    out.uv_indices.push_back({uv_at(i, j), uv_at(i + 1, j + 1), uv_at(i, j + 1)});
                }
            }
    }
    return out;
}

}  // namespace subdivtrace::testmesh

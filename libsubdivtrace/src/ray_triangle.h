#pragma once
// Watertight ray/triangle intersection (Woop, Benthin, Wald, JCGT 2013), in
// double precision: a ray that meets a shared edge or vertex is reported by at
// least one of the triangles that share it, never by none.

#include <cmath>
#include <utility>

#include <glm/common.hpp>

#include "subdivtrace/mesh.h"
#include "subdivtrace/shell.h"

namespace subdivtrace::detail {

/// The ray's shear constants, computed once per ray.
struct WatertightRay {
    Vec3 origin;
    int kx, ky, kz;
    double sx, sy, sz;
};

inline WatertightRay make_watertight_ray(const Vec3& origin, const Vec3& dir) {
    WatertightRay r;
    r.origin = origin;
    const Vec3 a = glm::abs(dir);
    r.kz = a.x > a.y ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
    r.kx = (r.kz + 1) % 3;
    r.ky = (r.kx + 1) % 3;
    // Keep the winding: swap x and y if the dominant component is negative.
    if (dir[r.kz] < 0.0) std::swap(r.kx, r.ky);
    r.sx = dir[r.kx] / dir[r.kz];
    r.sy = dir[r.ky] / dir[r.kz];
    r.sz = 1.0 / dir[r.kz];
    return r;
}

struct TriangleHit {
    double t;
    double b0, b1, b2;  ///< barycentric weights of corners 0, 1, 2
    /// Twice the triangle's signed area seen along the ray: its sign says
    /// which side the ray crossed from; exactly zero weights above mean the
    /// ray met an edge (one zero) or a corner (two), the same for every
    /// triangle that shares it (the edge functions are computed identically).
    double det;
};

/// Intersects both sides; true with t in (t_min, t_max).
inline bool intersect_watertight(const WatertightRay& r, const Vec3& p0, const Vec3& p1,
                                 const Vec3& p2, double t_min, double t_max, TriangleHit& hit) {
    const Vec3 a = p0 - r.origin, b = p1 - r.origin, c = p2 - r.origin;
    const double ax = a[r.kx] - r.sx * a[r.kz], ay = a[r.ky] - r.sy * a[r.kz];
    const double bx = b[r.kx] - r.sx * b[r.kz], by = b[r.ky] - r.sy * b[r.kz];
    const double cx = c[r.kx] - r.sx * c[r.kz], cy = c[r.ky] - r.sy * c[r.kz];
    double u = cx * by - cy * bx;
    double v = ax * cy - ay * cx;
    double w = bx * ay - by * ax;
    // Exactly zero edge functions: redo them in higher precision (the paper's fallback).
    if (u == 0.0 || v == 0.0 || w == 0.0) {
        using L = long double;
        u = static_cast<double>(L(cx) * L(by) - L(cy) * L(bx));
        v = static_cast<double>(L(ax) * L(cy) - L(ay) * L(cx));
        w = static_cast<double>(L(bx) * L(ay) - L(by) * L(ax));
    }
    if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return false;
    const double det = u + v + w;
    if (det == 0.0 || !std::isfinite(det)) return false;
    const double az = r.sz * a[r.kz], bz = r.sz * b[r.kz], cz = r.sz * c[r.kz];
    const double t_scaled = u * az + v * bz + w * cz;
    const double t = t_scaled / det;
    if (!(t > t_min && t < t_max)) return false;
    const double inv = 1.0 / det;
    hit.t = t;
    hit.b0 = u * inv;
    hit.b1 = v * inv;
    hit.b2 = w * inv;
    hit.det = det;
    return true;
}

}  // namespace subdivtrace::detail

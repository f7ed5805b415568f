#pragma once
/// \file spawn.h
/// Secondary rays that leave a hit without hitting the surface they left
/// (DESIGN.md section 5, pbrt's "re-intersect" property).

#include "subdivtrace/tracer.h"

namespace subdivtrace {

/// The ray from `hit` (found by `ray`) towards `target` (a point light): it
/// leaves the surface by the hit's error bound on the target's side (pbrt's
/// spawn-ray offset), ends at the target, carries the camera path length so
/// the footprint rule gives it the camera's resolution near its origin, and
/// follows the same view as `ray`.
Ray spawn_shadow_ray(const Ray& ray, const Hit& hit, const Vec3& target);

}  // namespace subdivtrace

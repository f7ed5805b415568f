#pragma once
// Finite-value checks shared by mesh validation (mesh.cpp) and the writers
// of subdivided meshes (write_mesh.cpp).

#include <cmath>
#include <string>
#include <vector>

#include "subdivtrace/mesh.h"

namespace subdivtrace::detail {

inline bool is_finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline bool is_finite(const Vec2& v) { return std::isfinite(v.x) && std::isfinite(v.y); }

/// Throws MeshError("<source>: <what> <i> is not finite (x, y, z)") at the
/// first value of `values` that is not finite.
void check_finite(const std::vector<Vec3>& values, const char* what, const std::string& source);
void check_finite(const std::vector<Vec2>& values, const char* what, const std::string& source);

}  // namespace subdivtrace::detail

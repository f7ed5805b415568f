#pragma once
// OpenMesh's uniform subdividers, the independent reference for Loop and
// Butterfly: the tests compare our meshes with their output and
// bench_uniform times them as the peer.
// OpenMesh's VectorT leaves default-constructed coordinates uninitialised on
// purpose; GCC 12 then warns inside <vector> (the includer must say so before
// its first include, as test_schemes.cpp and bench_uniform.cpp do).
#include <cstddef>

#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/ModifiedButterFlyT.hh>

#include "subdivtrace/scheme.h"

namespace subdivtrace::testmesh {

/// Subdivides `om` in place `levels` times with LoopT (scheme loop) or
/// ModifiedButterflyT (anything else).
template <class OmMesh>
void openmesh_subdivide(OmMesh& om, SchemeKind scheme, int levels) {
    if (scheme == SchemeKind::loop) {
        OpenMesh::Subdivider::Uniform::LoopT<OmMesh> loop;
        loop.attach(om);
        loop(static_cast<std::size_t>(levels));
        loop.detach();
    } else {
        OpenMesh::Subdivider::Uniform::ModifiedButterflyT<OmMesh> butterfly;
        butterfly.attach(om);
        butterfly(static_cast<std::size_t>(levels));
        butterfly.detach();
    }
}

}  // namespace subdivtrace::testmesh

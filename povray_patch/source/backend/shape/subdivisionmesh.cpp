/*******************************************************************************
 * subdivisionmesh.cpp
 *
 * This module implements the subdivision_mesh primitive: a thin adapter that
 * hands a triangle mesh to libsubdivtrace and maps its hits back to POV-Ray.
 *
 * ---------------------------------------------------------------------------
 * Part of the subdivtrace patch to POV-Ray 3.7 (see povray_patch/ in the
 * subdivtrace project). POV-Ray is free software under the GNU Affero
 * General Public License, version 3 or later; so is this file.
 *******************************************************************************/

/****************************************************************************
*
*  Syntax:
*
*  subdivision_mesh
*  {
*     mesh2 { vertex_vectors {...} [normal_vectors {...}] [uv_vectors {...}]
*             face_indices {...} [normal_indices {...}] [uv_indices {...}] }
*     | file "mesh.obj"
*     [scheme normal | loop | butterfly]
*     [tolerance PIXELS] [max_level LEVEL] [cache_mb MEGABYTES]
*     [OBJECT_MODIFIERS...]
*  }
*
*  Every ray descends the subdivision hierarchy of the mesh only as deep as
*  its footprint needs (libsubdivtrace, DESIGN.md section 5): the surface
*  looks smooth at any distance without tessellating it uniformly.
*
*****************************************************************************/

// libsubdivtrace first: its headers (GLM) must not see POV-Ray's DBL/SNGL
// macros or the X, Y, Z enumerators and global min/max of namespace pov.
#include "subdivtrace/mesh.h"
#include "subdivtrace/scheme.h"
#include "subdivtrace/tracer.h"
#if __has_include("subdivtrace/mesh_io.h")
#include "subdivtrace/mesh_io.h"
#define SUBDIVTRACE_HAVE_MESH_IO 1
#endif

#include <cmath>
#include <set>
#include <stdexcept>

// frame.h must always be the first POV file included (pulls in platform config)
#include "backend/frame.h"
#include "backend/math/vector.h"
#include "backend/math/matrices.h"
#include "backend/bounding/bbox.h"
#include "backend/scene/objects.h"
#include "backend/scene/camera.h"
#include "backend/scene/threaddata.h"
#include "backend/shape/subdivisionmesh.h"

// this must be the last file included
#include "base/povdebug.h"

namespace pov
{

/*****************************************************************************
* Local variables
******************************************************************************/

namespace
{

// The render summary keeps one counter per deepest level reached.
static_assert(subdivtrace::k_max_level_cap ==
              SubdivMesh_Deepest_Level_Last - SubdivMesh_Deepest_Level_0,
              "statspov.h needs one SubdivMesh_Deepest_Level counter per level");

// Per-thread scratch for All_Intersections (no allocation per ray once warm).
thread_local std::vector<subdivtrace::Hit> hit_scratch;

subdivtrace::Vec3 to_vec3(const VECTOR v)
{
	return subdivtrace::Vec3(v[X], v[Y], v[Z]);
}

void add_counters(TraceThreadData *Thread, const subdivtrace::TraceCounters& c)
{
	Thread->Stats()[SubdivMesh_Nodes_Visited] += c.nodes_visited;
	Thread->Stats()[SubdivMesh_Leaves_Tested] += c.leaves_tested;
	int level = c.deepest_level;
	if (level < 0)
		level = 0;
	if (level > subdivtrace::k_max_level_cap)
		level = subdivtrace::k_max_level_cap;
	Thread->Stats()[IntStatsIndex(SubdivMesh_Deepest_Level_0 + level)]++;
}

}

/*****************************************************************************
*
* FUNCTION
*
*   SubdivisionMeshInput
*
* DESCRIPTION
*
*   Defaults are the library's own.
*
******************************************************************************/

SubdivisionMeshInput::SubdivisionMeshInput()
{
	subdivtrace::SurfaceOptions defaults;
	Scheme = subdivtrace::scheme_name(defaults.scheme);
	Tolerance = defaults.tolerance;
	MaxLevel = defaults.max_level;
	CacheMB = int(defaults.cache_mb);
}

int SubdivisionMesh::Max_Level_Cap()
{
	return subdivtrace::k_max_level_cap;
}



/*****************************************************************************
*
* FUNCTION
*
*   Build
*
* DESCRIPTION
*
*   Converts the parsed arrays (or reads the file), validates them in the
*   library and builds the shared surface. Errors come back as text for the
*   parser, which reports them with the file and line.
*
******************************************************************************/

std::string SubdivisionMesh::Build(const SubdivisionMeshInput& input, std::vector<std::string>& warnings)
{
	try
	{
		subdivtrace::Mesh mesh;

		if (!input.File.empty())
		{
#ifdef SUBDIVTRACE_HAVE_MESH_IO
			mesh = subdivtrace::read_mesh(input.File, &warnings);
#else
			return input.File + ": this build of libsubdivtrace cannot read mesh files";
#endif
		}
		else
		{
			subdivtrace::MeshArrays arrays;
			for (size_t i = 0; i + 2 < input.Vertices.size(); i += 3)
				arrays.positions.push_back(subdivtrace::Vec3(input.Vertices[i], input.Vertices[i + 1], input.Vertices[i + 2]));
			for (size_t i = 0; i + 2 < input.Normals.size(); i += 3)
				arrays.normals.push_back(subdivtrace::Vec3(input.Normals[i], input.Normals[i + 1], input.Normals[i + 2]));
			for (size_t i = 0; i + 1 < input.UVs.size(); i += 2)
				arrays.uvs.push_back(subdivtrace::Vec2(input.UVs[i], input.UVs[i + 1]));
			for (size_t i = 0; i + 2 < input.FaceIndices.size(); i += 3)
				arrays.face_indices.push_back({{input.FaceIndices[i], input.FaceIndices[i + 1], input.FaceIndices[i + 2]}});
			for (size_t i = 0; i + 2 < input.NormalIndices.size(); i += 3)
				arrays.normal_indices.push_back({{input.NormalIndices[i], input.NormalIndices[i + 1], input.NormalIndices[i + 2]}});
			for (size_t i = 0; i + 2 < input.UVIndices.size(); i += 3)
				arrays.uv_indices.push_back({{input.UVIndices[i], input.UVIndices[i + 1], input.UVIndices[i + 2]}});
			mesh = subdivtrace::mesh_from_arrays(arrays, "mesh2", &warnings);
		}

		subdivtrace::SurfaceOptions options;
		std::optional<subdivtrace::SchemeKind> kind = subdivtrace::parse_scheme(input.Scheme);
		if (!kind)
			return "unknown subdivision scheme '" + input.Scheme + "'";
		options.scheme = *kind;
		options.tolerance = input.Tolerance;
		options.max_level = input.MaxLevel;
		options.cache_mb = size_t(input.CacheMB);

		surface = std::make_shared<subdivtrace::AdaptiveSurface>(std::move(mesh), options);
	}
	catch (const std::exception& e)
	{
		surface.reset();
		return e.what();
	}

	// An open mesh has no inside: like mesh2 without inside_vector it is a
	// patch, which CSG treats as such.
	if (surface->is_closed())
		Type &= ~PATCH_OBJECT;
	else
		Type |= PATCH_OBJECT;

	return std::string();
}

bool SubdivisionMesh::Is_Closed() const
{
	return surface && surface->is_closed();
}



/*****************************************************************************
*
* FUNCTION
*
*   Collect_Totals
*
* DESCRIPTION
*
*   Sums the node cache statistics of every distinct surface in the scene
*   (copies share one), searching CSG children, clipped_by and bounded_by.
*
******************************************************************************/

namespace
{

void collect_totals(const vector<ObjectPtr>& Objects, SubdivisionMeshTotals& Totals,
                    std::set<const subdivtrace::AdaptiveSurface *>& seen)
{
	for (vector<ObjectPtr>::const_iterator i = Objects.begin(); i != Objects.end(); i++)
	{
		ObjectPtr Object = *i;
		if (Object == NULL)
			continue;
		SubdivisionMesh *Subdiv = dynamic_cast<SubdivisionMesh *>(Object);
		if (Subdiv != NULL && Subdiv->Surface() != NULL && seen.insert(Subdiv->Surface()).second)
		{
			subdivtrace::SurfaceStats s = Subdiv->Surface()->stats();
			Totals.Surfaces++;
			Totals.NodesBuilt += s.nodes_built;
			Totals.CacheHits += s.trace.cache_hits;
			Totals.CacheMisses += s.trace.cache_misses;
			Totals.CacheEvictions += s.cache_evictions;
			Totals.CachePeakBytes += s.cache_peak_bytes;
		}
		if (CompoundObject *Compound = dynamic_cast<CompoundObject *>(Object))
			collect_totals(Compound->children, Totals, seen);
		collect_totals(Object->Clip, Totals, seen);
		collect_totals(Object->Bound, Totals, seen);
	}
}

}

void SubdivisionMesh::Collect_Totals(const vector<ObjectPtr>& Objects, SubdivisionMeshTotals& Totals)
{
	std::set<const subdivtrace::AdaptiveSurface *> seen;
	collect_totals(Objects, Totals, seen);
}



/*****************************************************************************
*
* FUNCTION
*
*   Set_View
*
* DESCRIPTION
*
*   Pixel angle for perspective cameras: horizontal field of view
*   2 atan(|Right| / (2 |Direction|)) over the image width. Orthographic
*   cameras: |Right| / width world units per pixel, taken into this copy's
*   object space by the transform's mean scale. Other projections use their
*   angle, if any, like perspective.
*
******************************************************************************/

void SubdivisionMesh::Set_View(const Camera& camera, int image_width)
{
	if (!surface)
		return;
	if (image_width < 1)
		image_width = 1;

	subdivtrace::View view;
	DBL right, direction;
	VLength(right, camera.Right);
	VLength(direction, camera.Direction);

	if (camera.Type == ORTHOGRAPHIC_CAMERA)
	{
		// Mean length of the world axes in object space.
		VECTOR axis, local;
		DBL scale = 0.0, len;
		for (int i = 0; i < 3; i++)
		{
			Make_Vector(axis, i == 0, i == 1, i == 2);
			MInvTransDirection(local, axis, Trans);
			VLength(len, local);
			scale += len / 3.0;
		}
		view.orthographic = true;
		view.pixel_size = right / image_width * scale;
		view.pixel_angle = 0.0;
	}
	else
	{
		DBL fov;
		if (camera.Type != PERSPECTIVE_CAMERA && camera.Angle > 0.0)
			fov = camera.Angle * M_PI / 180.0;
		else if (direction > 0.0)
			fov = 2.0 * atan(0.5 * right / direction);
		else
			fov = M_PI / 2.0;
		view.pixel_angle = fov / image_width;
	}

	MInvTransPoint(CameraLocal, camera.Location, Trans);
	HaveCamera = true;
	view.camera = to_vec3(CameraLocal);

	// The surface is shared between copies of this object; the last copy's
	// camera wins here, but every ray passes its own origin distance below.
	surface->set_view(view);
}



/*****************************************************************************
*
* FUNCTION
*
*   All_Intersections
*
* DESCRIPTION
*
*   The ray is taken into object space without normalising its direction, so
*   the library's ray parameter is POV-Ray's depth. All crossings are needed
*   only inside CSG and for clipped_by; otherwise the nearest will do.
*   Camera rays start at the
*   camera (origin distance 0); other rays start where a camera ray ended,
*   and the library sizes their footprint by the distance from the camera.
*
******************************************************************************/

bool SubdivisionMesh::All_Intersections(const Ray& ray, IStack& Depth_Stack, TraceThreadData *Thread)
{
	Thread->Stats()[Ray_SubdivMesh_Tests]++;

	if (!surface)
		return false;

	VECTOR P, D;
	MInvTransPoint(P, ray.Origin, Trans);
	MInvTransDirection(D, ray.Direction, Trans);

	subdivtrace::Ray local;
	local.origin = to_vec3(P);
	local.direction = to_vec3(D);
	local.t_min = MIN_ISECT_DEPTH;
	local.t_max = MAX_DISTANCE;
	if (ray.IsPrimaryRay())
		local.origin_distance = 0.0;
	else if (HaveCamera)
	{
		VECTOR Offset;
		VSub(Offset, P, CameraLocal);
		VLength(local.origin_distance, Offset);
	}

	subdivtrace::TraceCounters counters;
	std::vector<subdivtrace::Hit>& hits = hit_scratch;
	hits.clear();
	if (!(Type & IS_CHILD_OBJECT) && Clip.empty())
	{
		// Outside CSG and unclipped, POV-Ray uses only the nearest hit (as
		// fractal.cpp relies on): the library may stop at the first one.
		subdivtrace::Hit hit;
		if (surface->intersect(local, hit, &counters))
			hits.push_back(hit);
	}
	else
		surface->intersect_all(local, hits, &counters);
	add_counters(Thread, counters);

	bool found = false;
	for (size_t i = 0; i < hits.size(); i++)
	{
		const subdivtrace::Hit& hit = hits[i];
		if (!(hit.t > MIN_ISECT_DEPTH && hit.t < MAX_DISTANCE))
			continue;

		VECTOR IPoint, LocalNormal, INormal;
		UV_VECT UV;
		VEvaluateRay(IPoint, ray.Origin, hit.t, ray.Direction);
		if (!Clip.empty() && !Point_In_Clip(IPoint, Clip, Thread))
			continue;

		Make_Vector(LocalNormal, hit.normal.x, hit.normal.y, hit.normal.z);
		MTransNormal(INormal, LocalNormal, Trans);
		VNormalizeEq(INormal);
		UV[U] = hit.uv.x;
		UV[V] = hit.uv.y;

		Depth_Stack->push(Intersection(hit.t, IPoint, INormal, UV, this));
		found = true;
	}

	if (found)
		Thread->Stats()[Ray_SubdivMesh_Tests_Succeeded]++;
	return found;
}



/*****************************************************************************
*
* FUNCTION
*
*   Inside
*
* DESCRIPTION
*
*   Closed meshes only; an open mesh (a patch) has no inside.
*
******************************************************************************/

bool SubdivisionMesh::Inside(const VECTOR IPoint, TraceThreadData *) const
{
	if (!surface || !surface->is_closed())
		return false;

	VECTOR P;
	MInvTransPoint(P, IPoint, Trans);
	bool inside = surface->inside(to_vec3(P));

	if (Test_Flag(this, INVERTED_FLAG))
		return !inside;
	return inside;
}



/*****************************************************************************
*
* FUNCTION
*
*   Normal, UVCoord
*
* DESCRIPTION
*
*   Both were computed by the library when the hit was found.
*
******************************************************************************/

void SubdivisionMesh::Normal(VECTOR Result, Intersection *Inter, TraceThreadData *) const
{
	Assign_Vector(Result, Inter->INormal);
}

void SubdivisionMesh::UVCoord(UV_VECT Result, const Intersection *Inter, TraceThreadData *) const
{
	Assign_UV_Vect(Result, Inter->Iuv);
}



/*****************************************************************************
*
* FUNCTION
*
*   Translate, Rotate, Scale, Transform
*
* DESCRIPTION
*
*   All compose into Trans; the mesh itself never moves.
*
******************************************************************************/

void SubdivisionMesh::Translate(const VECTOR, const TRANSFORM *tr)
{
	Transform(tr);
}

void SubdivisionMesh::Rotate(const VECTOR, const TRANSFORM *tr)
{
	Transform(tr);
}

void SubdivisionMesh::Scale(const VECTOR, const TRANSFORM *tr)
{
	Transform(tr);
}

void SubdivisionMesh::Transform(const TRANSFORM *tr)
{
	if (Trans == NULL)
		Trans = Create_Transform();

	Compose_Transforms(Trans, tr);

	Compute_BBox();
}

void SubdivisionMesh::Invert()
{
	Invert_Flag(this, INVERTED_FLAG);
}



/*****************************************************************************
*
* FUNCTION
*
*   SubdivisionMesh, ~SubdivisionMesh, Copy
*
* DESCRIPTION
*
*   Copies share the surface (and so its node cache); each has its own
*   transform.
*
******************************************************************************/

SubdivisionMesh::SubdivisionMesh() : ObjectBase(SUBDIVISION_MESH_OBJECT)
{
	Trans = Create_Transform();
	Make_Vector(CameraLocal, 0.0, 0.0, 0.0);
	HaveCamera = false;
}

SubdivisionMesh::~SubdivisionMesh()
{
	Destroy_Transform(Trans);
}

ObjectPtr SubdivisionMesh::Copy()
{
	SubdivisionMesh *New = new SubdivisionMesh();

	Destroy_Transform(New->Trans);
	*New = *this;
	New->Trans = Copy_Transform(Trans);

	return (New);
}



/*****************************************************************************
*
* FUNCTION
*
*   Compute_BBox
*
* DESCRIPTION
*
*   The library's bounds hold the surface at every level up to max_level.
*
******************************************************************************/

void SubdivisionMesh::Compute_BBox()
{
	if (!surface)
	{
		Make_BBox(BBox, -BOUND_HUGE/2.0, -BOUND_HUGE/2.0, -BOUND_HUGE/2.0, BOUND_HUGE, BOUND_HUGE, BOUND_HUGE);
		return;
	}

	subdivtrace::Bounds3 b = surface->bounds();
	VECTOR mins, maxs;
	Make_Vector(mins, b.lo.x, b.lo.y, b.lo.z);
	Make_Vector(maxs, b.hi.x, b.hi.y, b.hi.z);
	Make_BBox_from_min_max(BBox, mins, maxs);

	Recompute_BBox(&BBox, Trans);
}

}

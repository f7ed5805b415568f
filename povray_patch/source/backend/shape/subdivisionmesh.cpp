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
*             [texture_list {...}] face_indices {...} [normal_indices {...}]
*             [uv_indices {...}] [inside_vector <x,y,z>] }
*     | file "mesh.obj" | MESH_IDENTIFIER
*     [scheme normal | loop | butterfly] [refine error | size]
*     [tolerance PIXELS] [max_level LEVEL] [weld EPS | no_weld]
*     [OBJECT_MODIFIERS...]
*  }
*
*  global_settings { subdivision_cache_mb MEGABYTES }
*
*  Every subdivision_mesh of a scene shares one tile cache with one budget
*  (subdivision_cache_mb); an object's own cache_mb is ignored with a warning.
*
*  Every ray descends the subdivision hierarchy of the mesh only as deep as
*  its footprint needs (libsubdivtrace, DESIGN.md section 5): the surface
*  looks smooth at any distance without tessellating it uniformly.
*
*****************************************************************************/

// libsubdivtrace first: its headers (GLM) must not see POV-Ray's DBL/SNGL
// macros or the X, Y, Z enumerators and global min/max of namespace pov.
#include "subdivtrace/mesh_report.h"
#include "subdivtrace/mesh.h"
#include "subdivtrace/scheme.h"
#include "subdivtrace/tile_cache.h"
#include "subdivtrace/tracer.h"
#if __has_include("subdivtrace/mesh_io.h")
#include "subdivtrace/mesh_io.h"
#define SUBDIVTRACE_HAVE_MESH_IO 1
#endif

#include <sys/stat.h>

#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
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
#include "backend/texture/texture.h"
#include "backend/shape/mesh.h"
#include "backend/shape/subdivisionmesh.h"

// this must be the last file included
#include "base/povdebug.h"

namespace pov
{

/*****************************************************************************
* Local typedefs
******************************************************************************/

/// What mesh2 keeps per triangle and the library does not: texture indices.
/// Indexed by the library's base face (faces the library drops are not here
/// either); shared by every copy of the object.
struct SubdivisionMeshFaces
{
	/// Three texture indices per face: one (then -1, -1), three, or none (-1).
	std::vector<long> Textures;
	/// The mesh has uvs (the library interpolates them); without, mesh2's uv
	/// is 0, 0.
	bool HasUVs;

	SubdivisionMeshFaces() : HasUVs(false) { }
};


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

/// Surfaces shared by every subdivision_mesh of a scene that gives the same
/// mesh (the same file, or the same arrays: a declared mesh or an inline
/// mesh2 written more than once) with the same settings, as copies of one
/// declared object share theirs: the mesh is built once, and the tiles one
/// object's rays build serve the others' (tiles do not depend on the view
/// or the object's transformation, so the pixels are those of separate
/// surfaces). Weak references: a surface lives as long as the objects that
/// use it.
struct SharedSurface
{
	std::weak_ptr<subdivtrace::AdaptiveSurface> Surface;
	std::weak_ptr<const SubdivisionMeshFaces> Faces;
};
std::mutex shared_surfaces_mutex;
std::map<std::string, SharedSurface> shared_surfaces;

/// Two 64-bit hashes of a sequence of words, with different multipliers,
/// so that two different meshes share a key with a chance of about 2^-128.
struct ContentHash
{
	uint64_t A, B;
	ContentHash() : A(0x9e3779b97f4a7c15ULL), B(0xc2b2ae3d27d4eb4fULL) { }
	void Word(uint64_t w)
	{
		A = (A ^ w) * 0x100000001b3ULL;
		A ^= A >> 29;
		B = (B ^ (w + 0x632be59bd9b4e019ULL)) * 0xff51afd7ed558ccdULL;
		B ^= B >> 32;
	}
	template <class T>
	void Array(const std::vector<T>& v)
	{
		Word(v.size());
		const unsigned char *bytes = reinterpret_cast<const unsigned char *>(v.data());
		const size_t n = v.size() * sizeof(T);
		size_t k = 0;
		for (; k + 8 <= n; k += 8)
		{
			uint64_t w;
			memcpy(&w, bytes + k, 8);
			Word(w);
		}
		uint64_t tail = 0;
		if (n > k)
			memcpy(&tail, bytes + k, n - k);
		Word(tail);
	}
};

/// What makes two subdivision_mesh blocks the same surface: the mesh (a
/// file's canonical path, device, inode, size and modification time, so an
/// edited file is read again; or the hashes of the arrays and per-face
/// texture indices) and every setting the surface holds, including the
/// scene's cache. Empty when a file cannot be found (the reader then
/// reports why) or there is no mesh.
std::string Shared_Surface_Key(const SubdivisionMeshInput& input)
{
	char settings[256];
	snprintf(settings, sizeof(settings), "\n%s %s %a %d %d %a %p", input.Scheme.c_str(), input.Refine.c_str(),
	         (double)input.Tolerance, input.MaxLevel, (int)input.Weld, (double)input.WeldTolerance,
	         (const void *)input.Cache.get());
	char mesh[PATH_MAX + 128];
	if (!input.File.empty())
	{
		char resolved[PATH_MAX];
		struct stat st;
		if (realpath(input.File.c_str(), resolved) == NULL || stat(resolved, &st) != 0)
			return std::string();
		snprintf(mesh, sizeof(mesh), "file %s\n%llu %llu %lld %lld.%09ld", resolved,
		         (unsigned long long)st.st_dev, (unsigned long long)st.st_ino, (long long)st.st_size,
		         (long long)st.st_mtim.tv_sec, (long)st.st_mtim.tv_nsec);
	}
	else if (input.Arrays)
	{
		const subdivtrace::MeshArrays& a = *input.Arrays;
		ContentHash h;
		h.Array(a.positions);
		h.Array(a.normals);
		h.Array(a.uvs);
		h.Array(a.face_indices);
		h.Array(a.normal_indices);
		h.Array(a.uv_indices);
		h.Array(input.FaceTextures);
		snprintf(mesh, sizeof(mesh), "arrays %016llx%016llx", (unsigned long long)h.A, (unsigned long long)h.B);
	}
	else
		return std::string();
	return std::string(mesh) + settings;
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
	Make_Vector(InsideVector, 0.0, 0.0, 0.0);
	subdivtrace::SurfaceOptions defaults;
	Scheme = subdivtrace::scheme_name(defaults.scheme);
	Refine = subdivtrace::refine_rule_name(defaults.refine);
	Tolerance = defaults.tolerance;
	MaxLevel = defaults.max_level;
	subdivtrace::WeldOptions weld;
	Weld = weld.enabled;
	WeldTolerance = weld.relative_tolerance;
}

/*****************************************************************************
*
* FUNCTION
*
*   Begin_List, Add_Vector, Add_UV, List_Size
*
* DESCRIPTION
*
*   The mesh2 body goes straight into the library's MeshArrays, with room
*   for the count mesh2 gives first (no copy when a list grows), up to 16 M
*   entries at once so that an absurd count asks for no memory before the
*   entries are there. Indices are checked by the library.
*
******************************************************************************/

void SubdivisionMeshInput::Begin_List(List list, long count)
{
	if (!Arrays)
		Arrays = std::make_shared<subdivtrace::MeshArrays>();
	const size_t room = (size_t)std::max(0L, std::min(count, 1L << 24));
	subdivtrace::MeshArrays& a = *Arrays;
	switch (list)
	{
		case VERTEX_LIST:       a.positions.clear();      a.positions.reserve(room);      break;
		case NORMAL_LIST:       a.normals.clear();        a.normals.reserve(room);        break;
		case UV_LIST:           a.uvs.clear();            a.uvs.reserve(room);            break;
		case FACE_LIST:         a.face_indices.clear();   a.face_indices.reserve(room);   break;
		case NORMAL_INDEX_LIST: a.normal_indices.clear(); a.normal_indices.reserve(room); break;
		case UV_INDEX_LIST:     a.uv_indices.clear();     a.uv_indices.reserve(room);     break;
	}
}

void SubdivisionMeshInput::Add_Vector(List list, const VECTOR v)
{
	subdivtrace::MeshArrays& a = *Arrays;
	switch (list)
	{
		case VERTEX_LIST:
			a.positions.emplace_back(v[X], v[Y], v[Z]);
			break;
		case NORMAL_LIST:
			a.normals.emplace_back(v[X], v[Y], v[Z]);
			break;
		case UV_LIST:
			a.uvs.emplace_back(v[X], v[Y]);
			break;
		default:
		{
			std::vector<std::array<std::int64_t, 3> >& indices =
				list == FACE_LIST ? a.face_indices : list == NORMAL_INDEX_LIST ? a.normal_indices : a.uv_indices;
			const std::array<std::int64_t, 3> triple = {{ (std::int64_t)v[X], (std::int64_t)v[Y], (std::int64_t)v[Z] }};
			indices.push_back(triple);
			break;
		}
	}
}

void SubdivisionMeshInput::Add_UV(const UV_VECT uv)
{
	Arrays->uvs.emplace_back(uv[U], uv[V]);
}

size_t SubdivisionMeshInput::List_Size(List list) const
{
	if (!Arrays)
		return 0;
	const subdivtrace::MeshArrays& a = *Arrays;
	switch (list)
	{
		case VERTEX_LIST:       return a.positions.size();
		case NORMAL_LIST:       return a.normals.size();
		case UV_LIST:           return a.uvs.size();
		case FACE_LIST:         return a.face_indices.size();
		case NORMAL_INDEX_LIST: return a.normal_indices.size();
		case UV_INDEX_LIST:     return a.uv_indices.size();
	}
	return 0;
}

/*****************************************************************************
*
* FUNCTION
*
*   Read_Mesh, Copy_Mesh_Textures
*
* DESCRIPTION
*
*   A mesh declared with mesh or mesh2, taken with everything mesh2 keeps per
*   triangle. Its transformation is applied to the vertices (its textures
*   were transformed with it already), so the subdivision_mesh starts with
*   the declared mesh's placement and takes modifiers of its own.
*
******************************************************************************/

void SubdivisionMeshInput::Read_Mesh(const Mesh& mesh)
{
	const MESH_DATA *Data = mesh.Data;
	VECTOR P, Q;
	bool smooth = false;

	Begin_List(VERTEX_LIST, Data->Number_Of_Vertices);
	for (long i = 0; i < Data->Number_Of_Vertices; i++)
	{
		Assign_Vector(Q, Data->Vertices[i]);
		if (mesh.Trans != NULL)
			MTransPoint(P, Q, mesh.Trans);
		else
			Assign_Vector(P, Q);
		Add_Vector(VERTEX_LIST, P);
	}

	Begin_List(UV_LIST, Data->Number_Of_UVCoords);
	for (long i = 0; i < Data->Number_Of_UVCoords; i++)
		Add_UV(Data->UVCoords[i]);

	// Mesh::Compute_Mesh_Triangle reorders some triangles (P1 <-> P2, with
	// their uvs, normals and textures) for its own intersection test; the
	// face normal it keeps (Normal_Ind) was computed before, as (P3 - P1) x
	// (P2 - P1), so it tells which were swapped: the subdivision needs the
	// consistent winding the user gave.
	std::vector<bool> swapped(Data->Number_Of_Triangles, false);
	Begin_List(FACE_LIST, Data->Number_Of_Triangles);
	Begin_List(UV_INDEX_LIST, Data->Number_Of_Triangles);
	FaceTextures.clear();
	for (long i = 0; i < Data->Number_Of_Triangles; i++)
	{
		const MESH_TRIANGLE& T = Data->Triangles[i];
		VECTOR P1, E1, E2, R, S;
		DBL d;
		Assign_Vector(P1, Data->Vertices[T.P1]);
		Assign_Vector(E1, Data->Vertices[T.P2]);
		Assign_Vector(E2, Data->Vertices[T.P3]);
		VSubEq(E1, P1);
		VSubEq(E2, P1);
		VCross(R, E1, E2);
		Assign_Vector(S, Data->Normals[T.Normal_Ind]);
		VDot(d, R, S);
		swapped[i] = (d > 0.0);
		const int a = swapped[i] ? 1 : 0, b = swapped[i] ? 0 : 1;

		const DBL face[3] = { (DBL)T.P1, (DBL)T.P2, (DBL)T.P3 };
		const DBL uv[3] = { (DBL)T.UV1, (DBL)T.UV2, (DBL)T.UV3 };
		const long long texture[3] = { T.Texture, T.ThreeTex ? T.Texture2 : -1, T.ThreeTex ? T.Texture3 : -1 };
		VECTOR face_in_order, uv_in_order;
		Make_Vector(face_in_order, face[a], face[b], face[2]);
		Make_Vector(uv_in_order, uv[a], uv[b], uv[2]);
		const long long texture_in_order[3] = { T.ThreeTex ? texture[a] : texture[0], T.ThreeTex ? texture[b] : -1, texture[2] };
		Add_Vector(FACE_LIST, face_in_order);
		if (Data->Number_Of_UVCoords > 0)
			Add_Vector(UV_INDEX_LIST, uv_in_order);
		if (mesh.Textures != NULL)
			FaceTextures.insert(FaceTextures.end(), texture_in_order, texture_in_order + 3);
		smooth = smooth || T.Smooth;
	}

	// Normals per corner: a smooth triangle's own, a flat one's face normal.
	Begin_List(NORMAL_LIST, smooth ? Data->Number_Of_Normals : 0);
	Begin_List(NORMAL_INDEX_LIST, smooth ? Data->Number_Of_Triangles : 0);
	if (smooth)
	{
		for (long i = 0; i < Data->Number_Of_Normals; i++)
		{
			Assign_Vector(Q, Data->Normals[i]);
			if (mesh.Trans != NULL)
			{
				MTransNormal(P, Q, mesh.Trans);
				VNormalizeEq(P);
			}
			else
				Assign_Vector(P, Q);
			Add_Vector(NORMAL_LIST, P);
		}
		for (long i = 0; i < Data->Number_Of_Triangles; i++)
		{
			const MESH_TRIANGLE& T = Data->Triangles[i];
			const DBL normal[3] = { (DBL)(T.Smooth ? T.N1 : T.Normal_Ind), (DBL)(T.Smooth ? T.N2 : T.Normal_Ind),
			                        (DBL)(T.Smooth ? T.N3 : T.Normal_Ind) };
			const int a = swapped[i] ? 1 : 0, b = swapped[i] ? 0 : 1;
			VECTOR normal_in_order;
			Make_Vector(normal_in_order, normal[a], normal[b], normal[2]);
			Add_Vector(NORMAL_INDEX_LIST, normal_in_order);
		}
	}

	for (size_t i = 0; i < Textures.size(); i++)
		Destroy_Textures(Textures[i]);
	Textures.clear();
	for (long i = 0; i < mesh.Number_Of_Textures; i++)
		Textures.push_back(Copy_Textures(mesh.Textures[i]));

	Make_Vector(InsideVector, 0.0, 0.0, 0.0);
	if (mesh.has_inside_vector)
		Assign_Vector(InsideVector, Data->Inside_Vect);
}

void SubdivisionMesh::Copy_Mesh_Textures(const Mesh& mesh)
{
	if (mesh.Texture != NULL)
		Texture = Copy_Textures(mesh.Texture);
	if (mesh.Interior_Texture != NULL)
		Interior_Texture = Copy_Textures(mesh.Interior_Texture);
	if (Test_Flag(&mesh, UV_FLAG))
		Set_Flag(this, UV_FLAG);
}

int SubdivisionMesh::Max_Level_Cap()
{
	return subdivtrace::k_max_level_cap;
}

std::shared_ptr<subdivtrace::TileCache> SubdivisionMesh::New_Scene_Cache()
{
	return std::make_shared<subdivtrace::TileCache>();
}

void SubdivisionMesh::Set_Cache_Budget(const std::shared_ptr<subdivtrace::TileCache>& cache, DBL mb)
{
	cache->set_budget(size_t(mb * 1048576.0));
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

std::string SubdivisionMesh::Build(SubdivisionMeshInput& input, std::vector<std::string>& warnings)
{
	const std::string shared_key = Shared_Surface_Key(input);
	if (!shared_key.empty())
	{
		std::lock_guard<std::mutex> lock(shared_surfaces_mutex);
		std::map<std::string, SharedSurface>::iterator it = shared_surfaces.find(shared_key);
		if (it != shared_surfaces.end())
		{
			surface = it->second.Surface.lock();
			faces = it->second.Faces.lock();
			if (!surface || !faces)
			{
				surface.reset();
				faces.reset();
			}
		}
	}
	if (surface)
	{
		input.Arrays.reset();
		return Finish_Build(input);
	}

	std::shared_ptr<SubdivisionMeshFaces> data = std::make_shared<SubdivisionMeshFaces>();

	try
	{
		subdivtrace::Mesh mesh;
		subdivtrace::WeldOptions weld;
		weld.enabled = input.Weld;
		weld.relative_tolerance = input.WeldTolerance;

		if (!input.File.empty())
		{
#ifdef SUBDIVTRACE_HAVE_MESH_IO
			mesh = subdivtrace::read_mesh(input.File, &warnings, weld);
#else
			return input.File + ": this build of libsubdivtrace cannot read mesh files";
#endif
		}
		else
		{
			if (!input.Arrays)
				return "mesh2: no vertex_vectors or face_indices";
			subdivtrace::WeldReport report;
			mesh = subdivtrace::mesh_from_arrays(*input.Arrays, "mesh2", &warnings, weld, &report);
			input.Arrays.reset();

			// Texture indices follow the faces the library kept (it drops
			// faces that repeat a vertex or that welding collapses) and the
			// corners of the ones it turned to agree with their neighbours.
			if (!input.FaceTextures.empty())
			{
				data->Textures.reserve(3 * report.kept_faces.size());
				std::vector<uint32_t>::const_iterator reversed = report.reversed_triangles.begin();
				for (size_t t = 0; t < report.kept_faces.size(); t++)
				{
					const size_t f = report.kept_faces[t];
					data->Textures.insert(data->Textures.end(), &input.FaceTextures[3 * f], &input.FaceTextures[3 * f + 3]);
					if (reversed != report.reversed_triangles.end() && *reversed == t)
					{
						std::swap(data->Textures[3 * t + 1], data->Textures[3 * t + 2]);
						++reversed;
					}
				}
			}
		}
		data->HasUVs = mesh.has_uvs();

		subdivtrace::SurfaceOptions options;
		std::optional<subdivtrace::SchemeKind> kind = subdivtrace::parse_scheme(input.Scheme);
		if (!kind)
			return "unknown subdivision scheme '" + input.Scheme + "'";
		options.scheme = *kind;
		const std::string normals_note = subdivtrace::given_normals_warning(mesh, *kind, input.File.empty() ? "mesh2" : input.File);
		if (!normals_note.empty())
			warnings.push_back(normals_note);
		if (!subdivtrace::parse_refine_rule(input.Refine, options.refine))
			return "unknown refine rule '" + input.Refine + "'";
		options.tolerance = input.Tolerance;
		options.max_level = input.MaxLevel;
		options.cache = input.Cache;

		surface = std::make_shared<subdivtrace::AdaptiveSurface>(std::move(mesh), options);
	}
	catch (const std::exception& e)
	{
		surface.reset();
		return e.what();
	}
	faces = data;

	if (!shared_key.empty())
	{
		std::lock_guard<std::mutex> lock(shared_surfaces_mutex);
		for (std::map<std::string, SharedSurface>::iterator it = shared_surfaces.begin(); it != shared_surfaces.end(); )
		{
			if (it->second.Surface.expired())
				shared_surfaces.erase(it++);
			else
				++it;
		}
		SharedSurface& entry = shared_surfaces[shared_key];
		entry.Surface = surface;
		entry.Faces = faces;
	}
	return Finish_Build(input);
}

std::string SubdivisionMesh::Finish_Build(SubdivisionMeshInput& input)
{
	// Like mesh2, a mesh with an inside_vector is a solid whose inside is the
	// parity of crossings along that vector. Without one, a closed mesh is a
	// solid (the library's parity test) and an open mesh is a patch.
	DBL len;
	VLength(len, input.InsideVector);
	HasInsideVector = (len > EPSILON);
	if (HasInsideVector)
		VInverseScale(InsideVect, input.InsideVector, len);
	if (HasInsideVector || surface->is_closed())
		Type &= ~PATCH_OBJECT;
	else
		Type |= PATCH_OBJECT;

	// Textures as mesh2 has them: Determine_Textures is asked when there is a
	// texture_list; the object is textured when every face has an index.
	Textures = input.Textures;
	if (!Textures.empty())
		Set_Flag(this, MULTITEXTURE_FLAG);
	bool fully_textured = !faces->Textures.empty();
	for (size_t f = 0; f < faces->Textures.size(); f += 3)
		fully_textured = fully_textured && (faces->Textures[f] >= 0);
	if (fully_textured)
		Type |= TEXTURED_OBJECT;

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
                    std::set<const subdivtrace::AdaptiveSurface *>& seen,
                    std::set<const subdivtrace::TileCache *>& caches)
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
			Totals.RefineRules |= Subdiv->Surface()->options().refine == subdivtrace::RefineRule::size ? 2 : 1;
			Totals.Hits += s.trace.hits;
			Totals.HitsAtMaxLevel += s.trace.hits_at_max_level;
			Totals.BoundSumPx += s.trace.error_bound_px_sum;
			Totals.BoundMaxPx = std::max(Totals.BoundMaxPx, s.trace.error_bound_px_max);
			// The scene's cache once, whichever surfaces share it.
			const subdivtrace::TileCache *cache = Subdiv->Surface()->options().cache.get();
			if (cache != NULL && caches.insert(cache).second)
			{
				const subdivtrace::TileCacheStats c = cache->stats();
				Totals.CacheEvictions += c.evictions;
				Totals.CachePeakBytes += c.peak_bytes;
				Totals.CacheBudgetBytes += c.budget_bytes;
			}
		}
		if (CompoundObject *Compound = dynamic_cast<CompoundObject *>(Object))
			collect_totals(Compound->children, Totals, seen, caches);
		collect_totals(Object->Clip, Totals, seen, caches);
		collect_totals(Object->Bound, Totals, seen, caches);
	}
}

}

void SubdivisionMesh::Collect_Totals(const vector<ObjectPtr>& Objects, SubdivisionMeshTotals& Totals)
{
	std::set<const subdivtrace::AdaptiveSurface *> seen;
	std::set<const subdivtrace::TileCache *> caches;
	collect_totals(Objects, Totals, seen, caches);
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

std::string SubdivisionMesh::Set_View(const Camera& camera, int image_width)
{
	if (!surface)
		return std::string();
	if (image_width < 1)
		image_width = 1;

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
		Orthographic = true;
		PixelSize = right / image_width * scale;
		PixelAngle = 0.0;
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
		Orthographic = false;
		PixelSize = 0.0;
		PixelAngle = fov / image_width;
	}

	MInvTransPoint(CameraLocal, camera.Location, Trans);
	HaveCamera = true;

	// The surface is shared between copies; the view is this copy's own and
	// travels with each of its rays (Ray::view) and inside tests.
	subdivtrace::View view;
	Make_View(view);
	try
	{
		subdivtrace::AdaptiveSurface::check_view(view);
	}
	catch (const std::exception& e)
	{
		return e.what();
	}
	return std::string();
}

void SubdivisionMesh::Make_View(subdivtrace::View& view) const
{
	view.pixel_angle = PixelAngle;
	view.camera = to_vec3(CameraLocal);
	view.orthographic = Orthographic;
	view.pixel_size = PixelSize;
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
*   Camera rays start at the camera (origin distance 0); other rays start
*   where a camera ray ended, and the library sizes their footprint by the
*   distance from the camera. Every ray carries this copy's view.
*
*   POV-Ray starts secondary rays (shadow, reflection, refraction, ...) at
*   the hit point itself, with no offset. The surface such a ray sees near
*   its origin may lie a little off the surface the parent ray hit (another
*   level, snapped edges, rounding): Hit::error_bound bounds that distance.
*   A hit whose leaf plane passes within its error bound of the origin is the
*   surface the ray left, and is skipped (DESIGN.md section 5). Camera rays
*   and Inside() never skip anything, so CSG sees every crossing.
*
******************************************************************************/

namespace
{

bool is_surface_left(const subdivtrace::Hit& hit, const subdivtrace::Vec3& origin)
{
	const subdivtrace::Vec3 d = origin - hit.point;
	const subdivtrace::Vec3& n = hit.geometric_normal;
	return std::fabs(d.x * n.x + d.y * n.y + d.z * n.z) <= hit.error_bound;
}

// A secondary ray that re-finds the surface it left at every step is not
// followed further than this (each step moves t_min past one such hit).
const int k_max_surface_left_skips = 8;

}

bool SubdivisionMesh::All_Intersections(const Ray& ray, IStack& Depth_Stack, TraceThreadData *Thread)
{
	Thread->Stats()[Ray_SubdivMesh_Tests]++;

	if (!surface)
		return false;

	VECTOR P, D;
	MInvTransPoint(P, ray.Origin, Trans);
	MInvTransDirection(D, ray.Direction, Trans);

	subdivtrace::View view;
	Make_View(view);

	subdivtrace::Ray local;
	local.origin = to_vec3(P);
	local.direction = to_vec3(D);
	local.t_min = MIN_ISECT_DEPTH;
	local.t_max = MAX_DISTANCE;
	if (HaveCamera)
		local.view = &view;
	if (ray.IsPrimaryRay())
		local.origin_distance = 0.0;
	else if (HaveCamera)
	{
		VECTOR Offset;
		VSub(Offset, P, CameraLocal);
		VLength(local.origin_distance, Offset);
	}
	const bool secondary = !ray.IsPrimaryRay() && !ray.IsSubsurfaceRay();

	subdivtrace::TraceCounters counters;
	std::vector<subdivtrace::Hit>& hits = hit_scratch;
	hits.clear();
	if (!(Type & IS_CHILD_OBJECT) && Clip.empty())
	{
		// Outside CSG and unclipped, POV-Ray uses only the nearest hit (as
		// fractal.cpp relies on): the library may stop at the first one.
		subdivtrace::Hit hit;
		for (int skips = 0; surface->intersect(local, hit, &counters); skips++)
		{
			if (!secondary || skips == k_max_surface_left_skips || !is_surface_left(hit, local.origin))
			{
				hits.push_back(hit);
				break;
			}
			local.t_min = hit.t;
		}
	}
	else
	{
		surface->intersect_all(local, hits, &counters);
		if (secondary)
		{
			size_t kept = 0;
			for (size_t i = 0; i < hits.size(); i++)
				if (!is_surface_left(hits[i], local.origin))
					hits[kept++] = hits[i];
			hits.resize(kept);
		}
	}
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

		// The library interpolates the mesh's uvs; mesh2 without uvs has 0, 0.
		UV[U] = faces->HasUVs ? hit.uv.x : 0.0;
		UV[V] = faces->HasUVs ? hit.uv.y : 0.0;
		const DBL b2 = hit.base_barycentric.x, b3 = hit.base_barycentric.y, b1 = 1.0 - b2 - b3;

		Intersection isect(hit.t, IPoint, INormal, UV, this);
		// Object-specific data for Determine_Textures: the base face and the
		// hit's barycentric weights on it.
		isect.i1 = int(hit.base_face);
		Make_Vector(isect.LocalIPoint, b1, b2, b3);
		Depth_Stack->push(isect);
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
*   With an inside_vector, mesh2's rule: the parity of crossings along that
*   vector. Otherwise closed meshes only (the library's parity test at this
*   copy's view); an open mesh (a patch) has no inside.
*
******************************************************************************/

bool SubdivisionMesh::Inside(const VECTOR IPoint, TraceThreadData *) const
{
	if (!surface || !(HasInsideVector || surface->is_closed()))
		return false;

	VECTOR P;
	MInvTransPoint(P, IPoint, Trans);

	subdivtrace::View view;
	Make_View(view);
	bool inside;
	if (HasInsideVector)
	{
		VECTOR D;
		MInvTransDirection(D, InsideVect, Trans);
		subdivtrace::Ray local;
		local.origin = to_vec3(P);
		local.direction = to_vec3(D);
		local.t_min = 0.0;
		if (HaveCamera)
			local.view = &view;
		std::vector<subdivtrace::Hit> crossings;
		surface->intersect_all(local, crossings);
		inside = (crossings.size() % 2) == 1;
	}
	else
		inside = surface->inside(to_vec3(P), HaveCamera ? &view : NULL);

	if (Test_Flag(this, INVERTED_FLAG))
		return !inside;
	return inside;
}



/*****************************************************************************
*
* FUNCTION
*
*   Determine_Textures
*
* DESCRIPTION
*
*   As Mesh::Determine_Textures: a face with three texture indices blends
*   them by the hit's barycentric weights on its base triangle (at any level,
*   so the blend is continuous across base edges), one index selects a
*   texture, none falls back to the object's texture.
*
******************************************************************************/

void SubdivisionMesh::Determine_Textures(Intersection *isect, bool hitinside, WeightedTextureVector& textures, TraceThreadData *)
{
	const long *tex = NULL;
	if (faces && !faces->Textures.empty())
		tex = &faces->Textures[3 * size_t(isect->i1)];

	if ((Interior_Texture != NULL) && (hitinside == true))
		textures.push_back(WeightedTexture(1.0, Interior_Texture));
	else if ((tex != NULL) && (tex[1] >= 0))
	{
		COLC w1 = COLC(isect->LocalIPoint[X]);
		COLC w2 = COLC(isect->LocalIPoint[Y]);
		COLC w3 = COLC(isect->LocalIPoint[Z]);
		COLC wsum = 1.0 / (w1 + w2 + w3);

		textures.push_back(WeightedTexture(w1 * wsum, Textures[tex[0]]));
		textures.push_back(WeightedTexture(w2 * wsum, Textures[tex[1]]));
		textures.push_back(WeightedTexture(w3 * wsum, Textures[tex[2]]));
	}
	else if ((tex != NULL) && (tex[0] >= 0))
		textures.push_back(WeightedTexture(1.0, Textures[tex[0]]));
	else if (Texture != NULL)
		textures.push_back(WeightedTexture(1.0, Texture));
}

void SubdivisionMesh::Test_Opacity()
{
	if ((Texture == NULL) || pov::Test_Opacity(Texture))
		Set_Flag(this, OPAQUE_FLAG);

	for (size_t i = 0; i < Textures.size(); i++)
		if ((Textures[i] != NULL) && !pov::Test_Opacity(Textures[i]))
			Clear_Flag(this, OPAQUE_FLAG);
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

	// As Mesh: the texture_list moves with the object unless uv-mapped.
	if (!Test_Flag(this, UV_FLAG))
		for (size_t i = 0; i < Textures.size(); i++)
			Transform_Textures(Textures[i], tr);

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
*   Copies share the surface (and so its node cache) and the per-face data;
*   each has its own transform, view and texture_list references.
*
******************************************************************************/

SubdivisionMesh::SubdivisionMesh() : ObjectBase(SUBDIVISION_MESH_OBJECT)
{
	Trans = Create_Transform();
	Make_Vector(CameraLocal, 0.0, 0.0, 0.0);
	HaveCamera = false;
	Orthographic = false;
	PixelAngle = 0.0;
	PixelSize = 0.0;
	Make_Vector(InsideVect, 0.0, 0.0, 0.0);
	HasInsideVector = false;
}

SubdivisionMesh::~SubdivisionMesh()
{
	Destroy_Transform(Trans);
	for (size_t i = 0; i < Textures.size(); i++)
		Destroy_Textures(Textures[i]);
}

ObjectPtr SubdivisionMesh::Copy()
{
	SubdivisionMesh *New = new SubdivisionMesh();

	Destroy_Transform(New->Trans);
	*New = *this;
	New->Trans = Copy_Transform(Trans);
	for (size_t i = 0; i < Textures.size(); i++)
		New->Textures[i] = Copy_Textures(Textures[i]);

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

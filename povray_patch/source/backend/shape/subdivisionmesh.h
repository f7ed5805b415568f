/*******************************************************************************
 * subdivisionmesh.h
 *
 * This module contains all defines, typedefs, and prototypes for
 * subdivisionmesh.cpp: the subdivision_mesh primitive, a triangle mesh traced
 * as the smooth limit surface of a subdivision scheme, refined per ray by
 * libsubdivtrace.
 *
 * ---------------------------------------------------------------------------
 * Part of the subdivtrace patch to POV-Ray 3.7 (see povray_patch/ in the
 * subdivtrace project). POV-Ray is free software under the GNU Affero
 * General Public License, version 3 or later; so is this file.
 *******************************************************************************/

#ifndef SUBDIVISIONMESH_H
#define SUBDIVISIONMESH_H

#include <memory>
#include <string>
#include <vector>

// The library's types stay out of this header: it is included after POV-Ray's
// own headers (whose DBL/X/Y/Z/min/max clash with GLM's), so only
// subdivisionmesh.cpp sees libsubdivtrace.
namespace subdivtrace
{
	class AdaptiveSurface;
	class TileCache;
	struct MeshArrays;
	struct View;
}

namespace pov
{

/*****************************************************************************
* Global preprocessor defines
******************************************************************************/

// Closed meshes are solid; open ones become patches (no inside) once built.
#define SUBDIVISION_MESH_OBJECT (BASIC_OBJECT)

// Largest cache_mb and subdivision_cache_mb accepted (1 TB).
#define SUBDIVISION_MESH_MAX_CACHE_MB 1048576.0


/*****************************************************************************
* Global typedefs
******************************************************************************/

class Camera;
class Mesh;
struct SubdivisionMeshFaces;

/// Node statistics summed over the distinct surfaces of a scene, and those
/// of the tile cache(s) they share (one per scene: budget, peak, evictions).
struct SubdivisionMeshTotals
{
	int Surfaces;
	POV_ULONG NodesBuilt;
	POV_ULONG CacheHits;
	POV_ULONG CacheMisses;
	POV_ULONG CacheEvictions;
	POV_ULONG CachePeakBytes;
	POV_ULONG CacheBudgetBytes;
	/// Rules in use: 1 error, 2 size, 3 both.
	int RefineRules;
	/// Hits reported, and the certified bound on their distance to the
	/// surface in pixels (Hit::surface_error_px): sum and largest.
	POV_ULONG Hits;
	POV_ULONG HitsAtMaxLevel;
	DBL BoundSumPx;
	DBL BoundMaxPx;

	SubdivisionMeshTotals() :
		Surfaces(0), NodesBuilt(0), CacheHits(0), CacheMisses(0), CacheEvictions(0), CachePeakBytes(0),
		CacheBudgetBytes(0), RefineRules(0), Hits(0), HitsAtMaxLevel(0), BoundSumPx(0.0), BoundMaxPx(0.0) { }
};

/// Everything the parser reads from a subdivision_mesh block, in plain types.
struct SubdivisionMeshInput
{
	/// Path of a mesh file ("file"), or empty when Arrays is used.
	std::string File;
	/// The mesh2 body (vertex_vectors, normal_vectors, uv_vectors and the
	/// three index lists), read straight into the library's arrays: the
	/// parser appends with Begin_List and Add_*, and Build releases them as
	/// soon as the library has made its mesh of them.
	std::shared_ptr<subdivtrace::MeshArrays> Arrays;
	enum List { VERTEX_LIST, NORMAL_LIST, UV_LIST, FACE_LIST, NORMAL_INDEX_LIST, UV_INDEX_LIST };
	/// Texture indices into Textures, three per face (mesh2's face_indices
	/// extras: -1 where a face gives fewer than three).
	std::vector<long long> FaceTextures;
	/// texture_list; the object built takes over these references.
	std::vector<TEXTURE *> Textures;
	/// mesh2's inside_vector (zero = none).
	VECTOR InsideVector;

	/// "normal", "loop" or "butterfly".
	std::string Scheme;
	/// "error" or "size" (libsubdivtrace's RefineRule).
	std::string Refine;
	DBL Tolerance;
	int MaxLevel;
	/// The scene's tile cache (global_settings' subdivision_cache_mb), shared
	/// by every subdivision_mesh; NULL = one of the library's default budget.
	std::shared_ptr<subdivtrace::TileCache> Cache;
	/// Coincident vertices become one (libsubdivtrace's WeldOptions):
	/// within WeldTolerance times the bounding-box diagonal, 0 = identical.
	bool Weld;
	DBL WeldTolerance;

	/// Defaults of libsubdivtrace's SurfaceOptions.
	SubdivisionMeshInput();

	/// Starts (or restarts) one list of the mesh2 body with room for the
	/// count mesh2 gives before it.
	void Begin_List(List list, long count);
	/// Appends a vertex, normal (list VERTEX_LIST, NORMAL_LIST) or index
	/// triple (FACE_LIST, NORMAL_INDEX_LIST, UV_INDEX_LIST).
	void Add_Vector(List list, const VECTOR v);
	void Add_UV(const UV_VECT uv);
	/// Entries in a list so far.
	size_t List_Size(List list) const;

	/// The arrays of a declared mesh or mesh2: vertices (its transformation
	/// applied), normals of smooth triangles (flat ones get their face
	/// normal), uvs, texture indices, a copy of its texture_list and its
	/// inside_vector.
	void Read_Mesh(const Mesh& mesh);
};

class SubdivisionMesh : public ObjectBase
{
	public:
		SubdivisionMesh();
		virtual ~SubdivisionMesh();

		virtual ObjectPtr Copy();

		virtual bool All_Intersections(const Ray&, IStack&, TraceThreadData *);
		virtual bool Inside(const VECTOR, TraceThreadData *) const;
		virtual void Normal(VECTOR, Intersection *, TraceThreadData *) const;
		virtual void UVCoord(UV_VECT, const Intersection *, TraceThreadData *) const;
		virtual void Translate(const VECTOR, const TRANSFORM *);
		virtual void Rotate(const VECTOR, const TRANSFORM *);
		virtual void Scale(const VECTOR, const TRANSFORM *);
		virtual void Transform(const TRANSFORM *);
		virtual void Invert();
		virtual void Compute_BBox();
		virtual void Determine_Textures(Intersection *, bool, WeightedTextureVector&, TraceThreadData *);

		/// Builds the surface from parsed input. Returns an empty string on
		/// success, else the reason (for the parser's Error()); warnings from
		/// the library are appended to `warnings`.
		/// The input's arrays are released once the library has its mesh.
		std::string Build(SubdivisionMeshInput& input, std::vector<std::string>& warnings);

		/// Keeps this copy's view of the final camera and image width (pixel
		/// angle of DESIGN.md section 5); called once parsing is complete.
		/// Returns an empty string, or why the view is unusable.
		std::string Set_View(const Camera& camera, int image_width);

		/// OPAQUE_FLAG from the object's texture and every texture_list entry
		/// (as Mesh::Test_Mesh_Opacity does).
		void Test_Opacity();

		/// The object texture, interior texture and uv_mapping flag of a
		/// declared mesh given as this object's mesh.
		void Copy_Mesh_Textures(const Mesh& mesh);

		/// True if every base edge has two triangles (the object has an inside).
		bool Is_Closed() const;

		/// Deepest max_level the library accepts.
		static int Max_Level_Cap();

		/// A scene's tile cache with the library's default budget, and the
		/// budget of global_settings { subdivision_cache_mb MB }.
		static std::shared_ptr<subdivtrace::TileCache> New_Scene_Cache();
		static void Set_Cache_Budget(const std::shared_ptr<subdivtrace::TileCache>& cache, DBL mb);

		/// The library's surface (NULL before Build succeeded).
		const subdivtrace::AdaptiveSurface *Surface() const { return surface.get(); }

		/// Sums the statistics of every distinct surface among Objects and
		/// their CSG children, clipping and bounding objects, and of every
		/// distinct tile cache they use (one per scene).
		static void Collect_Totals(const vector<ObjectPtr>& Objects, SubdivisionMeshTotals& Totals);

	private:
		/// Shared by all copies of the object; its tile cache is the scene's.
		std::shared_ptr<subdivtrace::AdaptiveSurface> surface;
		/// Per-face texture indices, shared by all copies.
		std::shared_ptr<const SubdivisionMeshFaces> faces;
		/// texture_list, one reference per copy (as Mesh keeps them).
		std::vector<TEXTURE *> Textures;
		/// Camera location in this copy's object space (origin distance of rays).
		VECTOR CameraLocal;
		bool HaveCamera;
		/// This copy's footprint (subdivtrace::View), in its object space.
		bool Orthographic;
		DBL PixelAngle;
		DBL PixelSize;
		/// Normalised inside_vector in object space, as mesh2 keeps it.
		VECTOR InsideVect;
		bool HasInsideVector;

		void Make_View(subdivtrace::View& view) const;
		/// Build's second half, once the surface and faces are set (read, or
		/// shared with an object that reads the same file): the inside test,
		/// the patch flag and the textures.
		std::string Finish_Build(SubdivisionMeshInput& input);
};

}

#endif

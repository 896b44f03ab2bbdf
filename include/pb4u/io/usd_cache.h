#pragma once
// USD caches in USD's text form (.usda), written and read without the USD library: one
// UsdGeomMesh per mesh (garment, body) with fixed faces and time-sampled `points`, which
// Blender (USD import, Mesh Sequence Cache), Houdini Solaris, Maya and usdview open.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace pb4u {

// One mesh of the cache: its triangles and its vertex positions at each time code.
struct UsdMeshSequence {
  std::string name;                     // prim name under the root prim ("Garment", "Body")
  Eigen::MatrixXi faces;                // m x 3 vertex indices, counter-clockwise (rightHanded)
  std::vector<Eigen::MatrixXd> frames;  // T matrices of n x 3 positions, m, y up
  Eigen::Vector3d display_color{0.7, 0.7, 0.7};  // primvars:displayColor, linear RGB in [0, 1]
};

struct UsdCache {
  std::vector<UsdMeshSequence> meshes;
  double fps = 30.0;           // timeCodesPerSecond and framesPerSecond
  double start_time_code = 0;  // time code of frame 0; frame t is at start_time_code + t
};

// Writes `cache` as a USD text layer: metersPerUnit = 1, upAxis = "Y", startTimeCode and
// endTimeCode spanning the frames, timeCodesPerSecond = framesPerSecond = fps, defaultPrim
// "pb4u" (an Xform) holding one Mesh per sequence (subdivisionScheme "none", doubleSided,
// a constant displayColor, time-sampled points and extent as point3f/float3, i.e. float32).
// Every mesh must have the same number of frames, each with the same vertex count. Written
// atomically; throws pb4u::Error naming `path` on inconsistent input.
void write_usd_cache(const std::string& path, const UsdCache& cache);

// Reads the Mesh prims of a USD text layer, at any depth, in file order: their prim names,
// faces (polygons fanned into triangles) and points (each time sample in time-code order, or
// the default value when there are none). Points are converted to metres and y up from the
// layer's metersPerUnit and upAxis; prim transforms are not applied. fps is the layer's
// timeCodesPerSecond (USD's default 24 where absent), start_time_code its first time sample.
// Throws pb4u::Error naming `path` (and the line) on a file that is not USD text, is
// malformed, or whose meshes are inconsistent (indices out of range, samples of differing
// vertex counts, no points).
UsdCache read_usd_cache(const std::string& path);

}  // namespace pb4u

#pragma once
// Mesh files in and out. Reading goes through assimp (OBJ, PLY, STL, glTF/GLB, FBX,
// DAE, ...): all meshes of the file are merged in world space, polygons triangulated,
// duplicate vertices welded, degenerate and unreferenced elements dropped. Writing
// produces OBJ or binary PLY, atomically.
#include <string>

#include "pb4u/mesh/clean.h"
#include "pb4u/mesh/triangle_mesh.h"

namespace pb4u {

struct MeshReadOptions {
  bool clean = true;                    // weld + drop degenerate/unreferenced elements
  double relative_weld_tolerance = 1e-6;  // times the bounding-box diagonal
};

// Throws pb4u::Error naming `path` on a missing, empty, unreadable or invalid file
// (no triangles, non-finite coordinates, out-of-range indices).
TriMesh read_mesh(const std::string& path, const MeshReadOptions& options = {},
                  CleanReport* report = nullptr);

// Writes by extension: ".obj" or ".ply". Throws pb4u::Error on other extensions or I/O failure.
void write_mesh(const std::string& path, const TriMesh& mesh);
void write_obj(const std::string& path, const TriMesh& mesh);
void write_ply(const std::string& path, const TriMesh& mesh);

// Lower-case extension including the dot, e.g. ".obj".
std::string file_extension(const std::string& path);

}  // namespace pb4u

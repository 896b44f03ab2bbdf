#include "pb4u/garment/import_garment.h"

#include "pb4u/io/mesh_io.h"
#include "pb4u/mesh/remesh.h"
#include "pb4u/util/error.h"

namespace pb4u {

TriMesh import_garment(const std::string& path, int target_triangles) {
  TriMesh mesh = read_mesh(path);
  try {
    return remesh_to_triangle_count(mesh, target_triangles);
  } catch (const Error& e) {
    fail_file(path, e.what());
  }
}

}  // namespace pb4u

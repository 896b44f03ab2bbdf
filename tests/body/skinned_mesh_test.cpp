// Skinned, animated meshes through assimp: a two-bone glTF strip written here.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "pb4u/body/skinned_mesh_import.h"
#include "pb4u/util/error.h"
#include "strip_gltf.h"
#include "test_util.h"

using namespace pb4u;

namespace {

std::string base64(const std::vector<unsigned char>& data) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < data.size(); i += 3) {
    unsigned v = data[i] << 16;
    if (i + 1 < data.size()) v |= data[i + 1] << 8;
    if (i + 2 < data.size()) v |= data[i + 2];
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += i + 1 < data.size() ? table[(v >> 6) & 63] : '=';
    out += i + 2 < data.size() ? table[v & 63] : '=';
  }
  return out;
}

template <class T>
void append(std::vector<unsigned char>& buf, std::initializer_list<T> values) {
  for (T v : values) {
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, &v, sizeof(T));
    buf.insert(buf.end(), bytes, bytes + sizeof(T));
  }
}

}  // namespace

// A 0.2 x 2 m strip along +y: rows at y = 0 (Root), 1 (half and half), 2 (Bone). Bone sits
// at y = 1 and its default node rotation is a quarter turn about z, different from the bind
// pose its inverse bind matrix encodes. Animation "bend": Bone 0 -> 90 deg about z and
// Root translated 0 -> 2 m along z over 1 s.
std::string test::strip_gltf() {
  std::vector<unsigned char> b;
  append<float>(b, {-0.1f, 0, 0, 0.1f, 0, 0, -0.1f, 1, 0, 0.1f, 1, 0, -0.1f, 2, 0, 0.1f, 2, 0});  // 0: 72
  append<uint16_t>(b, {0, 1, 3, 0, 3, 2, 2, 3, 5, 2, 5, 4});                                     // 72: 24
  for (int v = 0; v < 6; ++v) append<uint8_t>(b, {0, 1, 0, 0});                                  // 96: 24
  append<float>(b, {1, 0, 0, 0, 1, 0, 0, 0, .5f, .5f, 0, 0, .5f, .5f, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0});  // 120: 96
  append<float>(b, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1,                              // 216: 128
                    1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1});
  append<float>(b, {0, 1});                                                                       // 344: 8
  append<float>(b, {0, 0, 0, 1, 0, 0, 0.70710678f, 0.70710678f});                                 // 352: 32
  append<float>(b, {0, 0, 0, 0, 0, 2});                                                           // 384: 24
  const int offsets[9] = {0, 72, 96, 120, 216, 344, 352, 384, 408};
  std::string views;
  for (int v = 0; v < 8; ++v)
    views += std::string(v ? "," : "") + "{\"buffer\":0,\"byteOffset\":" + std::to_string(offsets[v]) +
             ",\"byteLength\":" + std::to_string(offsets[v + 1] - offsets[v]) + "}";
  return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0,2]}],
  "nodes":[{"name":"Root","children":[1]},
           {"name":"Bone","translation":[0,1,0],"rotation":[0,0,0.70710678,0.70710678]},
           {"name":"Strip","mesh":0,"skin":0}],
  "skins":[{"joints":[0,1],"inverseBindMatrices":4}],
  "meshes":[{"primitives":[{"attributes":{"POSITION":0,"JOINTS_0":2,"WEIGHTS_0":3},"indices":1}]}],
  "animations":[{"name":"bend","channels":[{"sampler":0,"target":{"node":1,"path":"rotation"}},
                                            {"sampler":1,"target":{"node":0,"path":"translation"}}],
                 "samplers":[{"input":5,"output":6},{"input":5,"output":7}]}],
  "buffers":[{"byteLength":408,"uri":"data:application/octet-stream;base64,)" + base64(b) + R"("}],
  "bufferViews":[)" + views + R"(],
  "accessors":[{"bufferView":0,"componentType":5126,"count":6,"type":"VEC3","min":[-0.1,0,0],"max":[0.1,2,0]},
               {"bufferView":1,"componentType":5123,"count":12,"type":"SCALAR"},
               {"bufferView":2,"componentType":5121,"count":6,"type":"VEC4"},
               {"bufferView":3,"componentType":5126,"count":6,"type":"VEC4"},
               {"bufferView":4,"componentType":5126,"count":2,"type":"MAT4"},
               {"bufferView":5,"componentType":5126,"count":2,"type":"SCALAR","min":[0],"max":[1]},
               {"bufferView":6,"componentType":5126,"count":2,"type":"VEC4"},
               {"bufferView":7,"componentType":5126,"count":2,"type":"VEC3"}]})";
}

namespace {

int find_vertex(const Eigen::MatrixXd& V, const Eigen::RowVector3d& p) {
  Eigen::Index i;
  (V.rowwise() - p).rowwise().norm().minCoeff(&i);
  return static_cast<int>(i);
}

}  // namespace

TEST(SkinnedMesh, GltfSkeletonBindPoseAndAnimationFollowTheFile) {
  const std::string path = test::temp_dir("skin") + "/strip.gltf";
  test::write_file(path, test::strip_gltf());
  const SkinnedMeshFile file = read_skinned_mesh(path, 30.0);
  const Body& body = file.body;
  ASSERT_EQ(body.skeleton.num_joints(), 2);
  EXPECT_EQ(body.skeleton.names[1], "Bone");
  EXPECT_EQ(body.mesh.num_faces(), 4);
  EXPECT_LT((body.weights.rowwise().sum().array() - 1).abs().maxCoeff(), 1e-6);
  // Re-posed to the default node pose: the top row turned a quarter about (0, 1, 0).
  const int top = find_vertex(body.mesh.V, Eigen::RowVector3d(-1.0, 1.1, 0.0));
  EXPECT_LT((body.mesh.V.row(top) - Eigen::RowVector3d(-1.0, 1.1, 0.0)).norm(), 1e-5);
  ASSERT_EQ(file.motions.size(), 1u);
  EXPECT_EQ(file.animation_names[0], "bend");
  const Motion& m = file.motions[0];
  ASSERT_EQ(m.num_frames(), 31);  // 1 s at 30 fps
  // Frame 0: bone straight, so the top row is back at y = 2 (the bind pose of the file).
  const Eigen::MatrixXd first = pose_body(body, m.frames[0]);
  EXPECT_LT((first.row(top) - Eigen::RowVector3d(0.1, 2.0, 0.0)).norm(), 1e-5);
  // Last frame: bent a quarter turn and carried 2 m along z by the root.
  const Eigen::MatrixXd last = pose_body(body, m.frames[30]);
  EXPECT_LT((last.row(top) - Eigen::RowVector3d(-1.0, 1.1, 2.0)).norm(), 1e-4);
  // Halfway the root is halfway.
  EXPECT_NEAR(m.frames[15].root.z(), 1.0, 1e-4);
}

TEST(SkinnedMesh, FilesWithoutBonesAreRejectedNamingTheFile) {
  const std::string path = test::temp_dir("noskin") + "/tri.obj";
  test::write_file(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  try {
    read_skinned_mesh(path);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("no bones"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_skinned_mesh(path + ".missing.gltf"), Error);
}

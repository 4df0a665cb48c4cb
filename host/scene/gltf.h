// glTF 2.0 import (.gltf with separate or embedded buffers, .glb) through
// Debian's tinygltf 2.7. Two uses: a .gltf/.glb file given to `caustica
// render` is a whole scene (load_gltf_scene: its meshes, materials, camera
// and KHR_lights_punctual lights), and a coursework scene's "mesh" shape may
// name one (scene_shapes.cpp: its triangles and materials under the shape's
// transform). scenes/FORMAT.md ("glTF 2.0 files") is the user's view of the
// mapping.
//
// Rules: every failure is one caustica::Error naming the file and the JSON
// pointer of what is wrong ("/accessors/3", "/nodes/2/children/0"); every
// feature we do not render is named once in a warning, never dropped
// silently. Sizes are checked before anything is allocated from them
// (host/limits.h): external files before they are read, accessor ranges
// against their buffer views and buffers, indices against vertex counts.
// The node graph is walked without recursion, so a cycle is an error, not a
// stack overflow or a hang.
#pragma once

#include <glm/glm.hpp>

#include <optional>
#include <string>
#include <vector>

#include "host/scene/load_scene.h"
#include "host/scene/mesh.h"
#include "host/scene/textures.h"

namespace caustica {

// By extension, case-insensitive: .gltf or .glb.
bool is_gltf_file(const std::string& path);

// A camera placed by a node: the file's /cameras/<index> seen from the
// node's world transform (glTF cameras look down their local -z, up +y).
struct GltfCamera {
  int index = 0;          // into the file's cameras array
  glm::vec3 position{0.0f}, forward{0.0f, 0.0f, -1.0f}, up{0.0f, 1.0f, 0.0f};
  float yfov_radians = 0.8f;
  float aspect = 0.0f;    // the file's aspectRatio, 0 when it gives none
};

// A KHR_lights_punctual light placed by a node (world space). Intensity is
// colour x intensity as the file gives them (candela for point and spot,
// lux for directional), taken as our radiometric units (FORMAT.md).
struct GltfLight {
  enum class Type { Point, Spot, Directional } type = Type::Point;
  std::string pointer;  // "/extensions/KHR_lights_punctual/lights/2"
  glm::vec3 position{0.0f}, direction{0.0f, 0.0f, -1.0f};
  glm::vec3 intensity{1.0f};
  float inner_cone = 0.0f, outer_cone = 0.7853982f;  // radians
};

struct GltfModel {
  // Triangles in the file's world space (node transforms applied), after
  // the mesh loaders' filter (mesh_internal::add_triangle: degenerate and
  // non-finite ones dropped and counted); `material` indexes `materials`,
  // -1 for glTF's default material. mesh.materials stays empty.
  Mesh mesh;
  std::vector<Material> materials;
  std::vector<GltfCamera> cameras;  // in node order
  std::vector<GltfLight> lights;    // in node order
  size_t camera_count = 0;          // entries of the file's cameras array
  std::vector<std::string> warnings;  // each names the file and a pointer
  glm::vec3 lo{0.0f}, hi{0.0f};  // bounds of the triangles (equal when there are none)
};

// Reads and converts `path`. Textures go into `textures` (embedded images
// as well as files); their indices are in the returned materials. `root`
// transforms the whole file (applied above its root nodes).
GltfModel import_gltf(const std::string& path, TextureLibrary& textures, const glm::dmat4& root = glm::dmat4(1.0));

// The same from bytes already read (the fuzz target calls it). External
// files (buffers, images) resolve against `base_dir`; with allow_files
// false every external reference is an error instead (fuzzing).
GltfModel import_gltf_bytes(const std::string& path, const std::string& bytes, const std::string& base_dir,
                            TextureLibrary& textures, bool allow_files = true,
                            const glm::dmat4& root = glm::dmat4(1.0));

// glTF's default material (no "material" on a primitive): base colour 1,
// metallic 1, roughness 1, as the spec defines it.
Material gltf_default_material();

// The camera load_gltf_scene uses when a file has none: looking along -z
// (the file's front view) at the centre of the bounds lo..hi, from where a
// sphere around them just fits the 45 degree vertical field of view.
CameraDesc gltf_default_camera(const glm::vec3& lo, const glm::vec3& hi);

// A whole scene from a glTF file: path mode, the camera options.gltf_camera
// picks (default: the first placed), its lights; FORMAT.md says what stands
// in where the file has no camera or no light.
Scene load_gltf_scene(const std::string& path, const LoadOptions& options = {});

}  // namespace caustica

// The in-memory scene: what the loader produces and everything downstream
// (feature analysis, BVH build, upload) consumes. Geometry, materials and
// lights are stored directly in their device layout (kernels/shared/types.h)
// so that upload is a copy, not a conversion.
#pragma once

#include <glm/glm.hpp>

#include <optional>
#include <string>
#include <vector>

#include "kernels/shared/types.h"

namespace caustica {

// The integrators. A scene file names one ("rendermode"); the CLI may pick
// another; the session decides once (host/app/session.cpp).
enum class RenderMode { Binary, Phong, Path };

struct CameraDesc {
  int width = 0;
  int height = 0;
  glm::vec3 position{0.0f};
  glm::vec3 look_at{0.0f, 0.0f, 1.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float fov_y_degrees = 45.0f;  // vertical field of view
  float exposure = 0.0f;        // the JSON "exposure", in stops (image scale 2^exposure)
  // Thin lens (student variants): 0 is a pinhole. Phong ignores both; a
  // sampler of the lens focuses on the plane at focus_distance along forward.
  float aperture_radius = 0.0f;
  float focus_distance = 0.0f;  // the loader sets |lookAt - position| when the file gives none
};

struct Scene {
  std::string source_path;  // file the scene came from (for messages)
  // A scene given as a document rather than a file (load_scene_document:
  // the Python module's load_dict): its JSON text, which stands for the
  // file's bytes where the scene's identity is hashed (no file to read
  // again). Empty for a scene read from a file.
  std::string document;
  RenderMode mode = RenderMode::Phong;  // the file's "rendermode" (phong when absent)
  int nbounces = 4;
  CameraDesc camera;
  glm::vec3 background{0.0f};
  // The file's lights in the one form the device reads (what each field
  // holds: kernels/lib/lights/<type>_light.h); select_probability and
  // select_cdf are set by the light table (host/lights/light_table.h).
  std::vector<Light> lights;
  // Where each of `lights` was written, for messages: its JSON pointer in
  // the file ("/scene/lightsources/3", a glTF light's node); "" where a
  // light was made another way (tests, generated scenes).
  std::vector<std::string> light_sources;
  // Ambient light colour from the file ("ambientlight", lights of type
  // "ambient"); unset when it gives none (phong then uses white). It scales
  // phong's ambient term ka * diffuse colour; see scenes/FORMAT.md.
  std::optional<glm::vec3> ambient_light;
  std::vector<Material> materials;
  std::vector<Sphere> spheres;
  std::vector<Cylinder> cylinders;
  std::vector<Triangle> triangles;
  // Empty, or one entry per triangle (vertex normals / texture coordinates).
  std::vector<TriangleShading> triangle_shading;
  // Empty, or one entry per triangle: tangents where some material has a
  // normal map, vertex colours where some mesh has COLOR_0 (types.h).
  std::vector<TriangleTangents> triangle_tangents;
  std::vector<TriangleColours> triangle_colours;
  std::vector<Texture> textures;
  std::vector<uint16_t> texels;  // IEEE half floats, 4 per texel (linear rgb + alpha, 1 where the image has none)

  // The scene's "environment" (host/lights/environment_light.h): an
  // equirectangular sky seen by rays that leave the scene, in place of
  // `background`; a light of its own in path mode.
  struct Environment {
    std::string source;     // the file, or a description of the generated sky, for messages
    int width = 0, height = 0;
    std::vector<float> rgb;  // linear radiance times "intensity", row-major from the top row, 3 per texel
    glm::mat3 rotation{1.0f};  // map -> world: "rotate" [x, y, z] degrees, R = Rz Ry Rx
    bool importance = true;    // sampled by luminance; false: uniformly over the sphere (comparisons)
  };
  std::optional<Environment> environment;

  // Path mode only (add_light_geometry, host/lights/light_table.h): the
  // area lights' own geometry, appended after the file's shapes so that
  // BSDF-sampled rays can hit them; each primitive names its light (an
  // index into `lights`) and itself (a PRIM_* reference, types.h).
  struct LightPrimitive {
    uint32_t light = 0;
    uint32_t prim = 0;
  };
  struct LightGeometry {
    bool added = false;
    std::vector<LightPrimitive> prims;
  } light_geometry;

  struct MeshInfo {
    std::string file;
    size_t triangles = 0;         // added to the scene
    size_t dropped_degenerate = 0;
    double load_ms = 0.0;
  };
  std::vector<MeshInfo> meshes;

  size_t primitive_count() const { return spheres.size() + cylinders.size() + triangles.size(); }
  size_t light_count() const { return lights.size(); }
};

// Zero (or float-noise) area: sin of the corner angle below ~1e-7; also any
// non-finite vertex.
bool degenerate_triangle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c);

// Removes the shapes nothing can render (a zero or non-finite radius,
// height or axis, a degenerate triangle) from a scene built in code or
// edited after loading: the loader already refuses or drops them in files,
// and the BVH and kernels must never see one. Returns one message per
// dropped shape, naming it by type and index (at most 8, then a count).
std::vector<std::string> drop_degenerate_shapes(Scene& scene);

inline cs_float4 to_float4(const glm::vec3& v, float w = 0.0f) { return cs_float4{v.x, v.y, v.z, w}; }
inline glm::vec3 to_vec3(const cs_float4& v) { return glm::vec3(v.x, v.y, v.z); }
// A triangle's vertex colours as stored (half floats); null: white.
TriangleColours vertex_colours(const glm::vec4* rgba);
// A zeroed Material with its "none" markers set: no texture of any kind
// (-1), map scales and alpha 1, roughness not given (-1), index 1. Every
// material the loaders make starts from it.
Material blank_material();

// Camera basis per the coursework convention: right = up x forward, so with
// forward +z and up +y, world +x is on the image's right.
struct CameraBasis {
  glm::vec3 forward, right, up;
};
CameraBasis camera_basis(const CameraDesc& camera);

// A point within the scene's coordinate limit (limits::kMaxSceneCoordinate
// on every axis, finite); and, for messages, why a point beyond it is
// refused: "at (x, y, z), beyond +-1e12 scene units (...)".
bool within_coordinate_limit(const glm::dvec3& p);
std::string beyond_coordinate_limit(const glm::dvec3& p);

// The device camera for a width x height image (kernels/shared/camera.h
// turns it into rays); pixel_offset 0, pixel_count the whole image.
CameraGPU camera_for_image(const CameraDesc& camera, int width, int height);

const char* render_mode_name(RenderMode mode);

}  // namespace caustica

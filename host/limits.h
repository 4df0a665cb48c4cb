// Every size limit on input, in one place (README "Limits" lists them for
// users). A request beyond one is refused before anything is allocated, with
// an error that names the limit; nothing caustica reads may run it out of
// memory or into a crash instead. The values leave room for every scene,
// mesh and texture we know of (the largest: a 16k x 8k environment map, the
// 346k-face armadillo, generated scenes of a million shapes) while keeping
// each single allocation a parser makes for one file within a few GiB.
#pragma once

#include <cstdint>

namespace caustica::limits {

// Files are read whole; these bound the read itself (host/read_file.h).
inline constexpr uint64_t kMaxSceneFileBytes = uint64_t(1) << 30;    // 1 GiB of JSON
inline constexpr uint64_t kMaxMeshFileBytes = uint64_t(2) << 30;     // 2 GiB .obj / .ply
inline constexpr uint64_t kMaxMaterialFileBytes = uint64_t(64) << 20; // 64 MiB .mtl
inline constexpr uint64_t kMaxImageFileBytes = uint64_t(1) << 30;    // textures, references, diff inputs

// JSON nesting: the scene format itself is at most 5 levels deep; the bound
// keeps every recursive walk of the document (nlohmann's dump, copies,
// comparisons) far from the stack's end.
inline constexpr int kMaxJsonDepth = 64;

// Rendered images: the side limit is the camera's own ("width"/"height" in
// the scene file), the pixel limit keeps the film's 32-bit value offsets
// valid (3 values per pixel, 2^31 at most) with room to spare. The device's
// own limits (CL_DEVICE_MAX_MEM_ALLOC_SIZE, global memory) are checked
// separately, before any buffer is created (host/app/session.cpp).
inline constexpr int kMaxImageSide = 32768;
inline constexpr uint64_t kMaxImagePixels = uint64_t(1) << 28;  // 268,435,456, e.g. 16384 x 16384

// Render state files (host/render/render_state.h): the largest a render
// within kMaxImagePixels writes: per pixel two 128-bit sums of 3 channels
// (the sum and the half, 96 bytes), its samples, half start and ray count,
// and an adaptive weight (24 bytes), with the photon pass its SPPM
// statistics and visible point (160 bytes); a photon map of at most 2^22
// photons of 48 bytes (--photons' limit); and 1 MiB for the header, the
// identity and the schedule.
inline constexpr uint64_t kMaxStateFileBytes =
    (120 + 160) * kMaxImagePixels + 48 * (uint64_t(1) << 22) + (uint64_t(1) << 20);

// Exposure in stops (the camera's "exposure", --exposure): every pixel is
// scaled by 2^exposure, which must stay a normal float either way.
inline constexpr float kMaxExposureStops = 64.0f;
// --time, --write-every, --checkpoint-every: at most this many seconds
// (about 31 years; a larger or non-finite one is refused, not waited for).
inline constexpr double kMaxSeconds = 1e9;

// Textures: per side and per image, checked on the header before any pixel
// is decoded. A file must also be large enough to hold what it declares:
// no format we read stores more than kMaxPixelsPerFileByte pixels per byte
// (deflate's 1032:1 at 8 one-bit pixels per byte is the densest; PNG's
// bound is computed from its bit depth), and formats with at most run-length
// coding (BMP, TGA, HDR, PSD) no more than kMaxPixelsPerFileByteRle. So a
// 20-byte header declaring 16384 x 16384 is refused without decoding, and a
// 16 KB TGA cannot make stb fill a 2^27-pixel image from bytes past its end.
inline constexpr int kMaxTextureSide = 16384;
inline constexpr uint64_t kMaxTexturePixels = uint64_t(1) << 27;  // 134,217,728, e.g. 16384 x 8192
inline constexpr uint64_t kMaxPixelsPerFileByte = 8256;
inline constexpr uint64_t kMaxPixelsPerFileByteRle = 256;

// Phong (Whitted) shading traces one shadow ray per light from every
// shading point; its shadow queue grows with the light count (host/render/
// integrator_phong.cpp), so the number of point lights it is given (area and
// sphere lights count as one stand-in each) is bounded. Path mode samples
// lights and has no such limit.
inline constexpr uint64_t kMaxPhongLights = 1024;
// Scene coordinates (positions, centres, vertices, corners, translations,
// the camera) lie within +-kMaxSceneCoordinate, and sizes (radii,
// half-heights, light extents, the lens) are at most that, in scene units.
// The kernels square distances and the triangle test multiplies three
// coordinate differences (its determinants), which must stay finite in
// float32: (2e12)^3 x 3 = 2.4e37 < 3.4e38. A scene 1e30 across overflowed
// there (and its lights' power) instead of rendering; it is refused with
// the key or the mesh that put a point that far (scale the scene down).
inline constexpr float kMaxSceneCoordinate = 1e12f;
// Colours and coefficients that scale reflected light (diffusecolor, kd,
// specularcolor, ks, ka, checker colours): 1 reflects all of it; the
// community scenes go up to 9. Far above is a typo or a unit mistake.
inline constexpr float kMaxReflectance = 100.0f;

// glTF (host/scene/gltf*.cpp): files (.gltf, .glb and the buffers and
// images they name) are read under kMaxMeshFileBytes, so an accessor in a
// buffer is bounded by the file; one without a buffer view (all zeros,
// bounded by nothing else) may claim at most kMaxGltfZeroAccessorElements.
// The node graph is walked at most this deep and places at most this many
// node instances (a graph whose nodes share children multiplies); the
// triangles all mesh instances add, counted before degenerate ones are
// dropped, are bounded before they are stored (each costs some 250 bytes on
// the host on its way to the device: 4 GiB at the limit).
inline constexpr uint64_t kMaxGltfZeroAccessorElements = uint64_t(1) << 20;
inline constexpr int kMaxGltfNodeDepth = 1024;
inline constexpr uint64_t kMaxGltfNodeInstances = uint64_t(1) << 20;
inline constexpr uint64_t kMaxGltfTriangles = uint64_t(1) << 24;

}  // namespace caustica::limits

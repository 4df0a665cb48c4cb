// The 30 community scenes in ../shared/scenes-coursework/community (student
// variants of the coursework format, PROVENANCE.md there): each must load
// for a phong render or fail with a caustica::Error naming the file, never
// another exception or a crash. The table below pins which load and what
// they contain, so a loader change that loses a variant is caught.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <string>

#include "host/error.h"
#include "host/scene/load_scene.h"
#include "host/lights/light_table.h"
#include "host/lights/light_types.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

struct Expected {
  bool loads;
  // When it loads: primitive counts. Otherwise: a part of the error message.
  size_t spheres = 0, cylinders = 0, triangles = 0;
  const char* error = "";
};

Expected loads(size_t spheres, size_t cylinders, size_t triangles) { return {true, spheres, cylinders, triangles}; }
Expected fails(const char* error) { return {false, 0, 0, 0, error}; }

const std::map<std::string, Expected>& expected_outcomes() {
  static const std::map<std::string, Expected> table = {
      {"AshleyDong34__RayTracer__scene1.json", loads(3, 1, 4)},
      {"HlnnnWnng__High-Performance-Raytracer-Image-Render__Aperature_Test.json", loads(0, 0, 0)},
      // models/CompleteScene.obj (2.8 MB) was not saved with the corpus.
      {"HlnnnWnng__High-Performance-Raytracer-Image-Render__LightSampling_test.json",
       fails("/scene/shapes/0/filename: expected an existing mesh file, got \"models/CompleteScene.obj\"")},
      {"HlnnnWnng__High-Performance-Raytracer-Image-Render__obj_scene.json", loads(0, 0, 0)},
      {"Kierandon__cpp-raytracer__cornell_box.json", loads(1, 1, 24)},
      {"Kierandon__cpp-raytracer__path_dof.json", loads(1, 1, 16)},
      {"Kierandon__cpp-raytracer__scene_textures.json", loads(1, 1, 4)},
      {"Nebula1253__cpp-raytracer__scene_phong_refractive_textured.json", loads(3, 1, 2)},
      {"Ninteedo__CGRaytracer__glass_spheres_pathtraced.json", loads(1, 1, 2)},
      {"Ninteedo__CGRaytracer__initial_scene.json", loads(3, 9, 18)},
      {"S1958600__CGRCW2__cluttered_scene.json", loads(6, 2, 2)},
      {"Trenza1ore__std-raytracer__phong_scene.json", loads(3, 1, 2)},
      {"Trenza1ore__std-raytracer__scene_render.json", loads(18, 1, 0)},
      {"bartMn__ray-tracer-cpp__animation.json", loads(2, 1, 12)},
      {"chenyang9779__CGR-CW2-raytracer__scene_aperture.json", loads(3, 1, 2)},
      {"chxag__CGR-Raytracing-CW2__complex_three.json", loads(13, 9, 8)},
      {"chxag__CGR-Raytracing-CW2__cylinder_textures.json", loads(0, 3, 0)},
      {"chxag__CGR-Raytracing-CW2__sphere_cylinder_triangle_textured.json", loads(2, 1, 1)},
      {"constancefr__cgr_cw2__bvh_stress_test.json", loads(3, 5, 2)},
      {"constancefr__cgr_cw2__phong_texture_area_light.json", loads(1, 1, 2)},
      {"david14higgins__Pathtracer__area_lighting_pathtracer.json", loads(1, 1, 2)},
      {"david14higgins__Pathtracer__complex_scene.json", loads(1000, 0, 0)},
      {"david14higgins__Pathtracer__pathtracer_lens_sampling.json", loads(3, 1, 2)},
      {"david14higgins__Pathtracer__textures.json", loads(1, 1, 2)},
      {"epuzio__RaeTracer__capybara.json", loads(0, 0, 79)},
      {"epuzio__RaeTracer__simple_phong_with_texture.json", loads(1, 1, 2)},
      {"jayp97__raytracing-renderer__scene_texture.json", loads(3, 1, 3)},
      {"michaelzhang4__raytracer__400_spheres.json", loads(484, 0, 2)},
      {"michaelzhang4__raytracer__pathtracer_scene.json", loads(3, 1, 2)},
      {"mrinalraj860__Advanced-Ray-Tracing-and-Path-Tracing-Renderer__With_emmision.json", loads(3, 0, 1)},
  };
  return table;
}

std::string pad(std::string s, size_t n) {
  if (s.size() > n) return s.substr(0, n - 3) + "...";
  return s + std::string(n - s.size(), ' ');
}

TEST(CommunityCorpus, EveryFileLoadsOrFailsCleanly) {
  CAUSTICA_REQUIRE_SHARED(shared);
  const auto dir = std::filesystem::path(shared) / "scenes-coursework" / "community";
  if (!std::filesystem::is_directory(dir)) GTEST_SKIP() << "no community scenes in " << dir;
  std::map<std::string, std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (entry.path().extension() == ".json") files[entry.path().filename().string()] = entry.path();
  EXPECT_EQ(files.size(), expected_outcomes().size());

  std::printf("%s | outcome\n", pad("community scene", 72).c_str());
  for (const auto& [name, path] : files) {
    LoadOptions options;
    std::vector<std::string> warnings;
    options.warnings = &warnings;
    std::string outcome;
    bool loaded = false;
    Scene scene;
    try {
      scene = load_scene(path.string(), options);
      loaded = true;
      outcome = "loads: " + std::to_string(scene.primitive_count()) + " shapes (" + std::to_string(scene.spheres.size()) +
                " spheres, " + std::to_string(scene.cylinders.size()) + " cylinders), " +
                std::to_string(scene.triangles.size()) + " tris, " + std::to_string(scene.light_count()) +
                " lights, " + std::to_string(scene.textures.size()) + " textures, " + std::to_string(warnings.size()) +
                " warnings";
    } catch (const Error& e) {
      outcome = std::string("error: ") + e.what();
      EXPECT_NE(outcome.find(path.string()), std::string::npos) << "the message must name the file: " << outcome;
    } catch (const std::exception& e) {
      ADD_FAILURE() << name << ": threw a " << typeid(e).name() << " instead of caustica::Error: " << e.what();
      continue;
    }
    std::printf("%s | %s\n", pad(name, 72).c_str(), outcome.c_str());

    auto it = expected_outcomes().find(name);
    if (it == expected_outcomes().end()) {
      ADD_FAILURE() << name << " is not in the expected-outcome table; add it (" << outcome << ")";
      continue;
    }
    const Expected& want = it->second;
    EXPECT_EQ(loaded, want.loads) << name << ": " << outcome;
    if (loaded && want.loads) {
      EXPECT_EQ(scene.spheres.size(), want.spheres) << name;
      EXPECT_EQ(scene.cylinders.size(), want.cylinders) << name;
      if (want.triangles > 0 || scene.meshes.empty())
        EXPECT_EQ(scene.triangles.size(), want.triangles) << name;
      else
        EXPECT_GT(scene.triangles.size(), 0u) << name << ": its meshes added no triangles";
      EXPECT_TRUE(scene.triangle_shading.empty() || scene.triangle_shading.size() == scene.triangles.size()) << name;
      for (const Material& m : scene.materials)
        EXPECT_LT(m.texture, static_cast<int>(scene.textures.size())) << name;
    } else if (!loaded && !want.loads) {
      EXPECT_NE(outcome.find(want.error), std::string::npos) << name << ": " << outcome;
    }
  }
}

// Variant features of particular corpus files, checked on the real files.
TEST(CommunityCorpus, VariantsLandInTheCanonicalFields) {
  CAUSTICA_REQUIRE_SHARED(shared);
  const std::string dir = shared + "/scenes-coursework/community/";
  if (!std::filesystem::is_directory(dir)) GTEST_SKIP() << "no community scenes";
  LoadOptions options;
  std::vector<std::string> warnings;
  options.warnings = &warnings;

  // camera "finiteAperture" + apertureSize (a diameter) + focusDistance; spherelight.
  Scene s = load_scene(dir + "Ninteedo__CGRaytracer__initial_scene.json", options);
  EXPECT_FLOAT_EQ(s.camera.aperture_radius, 0.005f);
  EXPECT_FLOAT_EQ(s.camera.focus_distance, 1.25f);
  ASSERT_EQ(lights_of_kind(s, LIGHT_SPHERE).size(), 1u);
  EXPECT_FLOAT_EQ(lights_of_kind(s, LIGHT_SPHERE)[0].p0.w, 0.1f);  // the radius
  EXPECT_TRUE(lights_of_kind(s, LIGHT_POINT).empty());
  ASSERT_EQ(whitted_lights(s).size(), 1u);  // its phong stand-in
  EXPECT_FALSE(s.triangle_shading.empty());

  // Top-level use_dof / aperture / focus_distance; emissive rectangle; box.
  s = load_scene(dir + "Kierandon__cpp-raytracer__path_dof.json", options);
  EXPECT_FLOAT_EQ(s.camera.aperture_radius, 0.3f);
  EXPECT_FLOAT_EQ(s.camera.focus_distance, 6.0f);
  bool emissive = false;
  for (const Material& m : s.materials) emissive |= m.emission.x > 0.0f;
  EXPECT_TRUE(emissive);

  // Area light with size [w, h] plus an "ambient" light; PLY meshes.
  s = load_scene(dir + "Trenza1ore__std-raytracer__scene_render.json", options);
  ASSERT_EQ(lights_of_kind(s, LIGHT_RECT).size(), 3u);
  EXPECT_FLOAT_EQ(glm::length(to_vec3(lights_of_kind(s, LIGHT_RECT)[0].p1)), 0.1f);
  EXPECT_EQ(s.ambient_light.value_or(glm::vec3(-1.0f)), glm::vec3(0.2f));
  EXPECT_FLOAT_EQ(s.camera.aperture_radius, 0.000625f);  // "diameter": 0.00125
  EXPECT_EQ(s.meshes.size(), 26u);

  // Scene-level ambientlight and an OBJ mesh with its MTL.
  s = load_scene(dir + "HlnnnWnng__High-Performance-Raytracer-Image-Render__obj_scene.json", options);
  EXPECT_EQ(s.ambient_light.value_or(glm::vec3(-1.0f)), glm::vec3(0.2f));
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_GT(s.meshes[0].triangles, 0u);

  // Procedural checkerboard texture.
  s = load_scene(dir + "jayp97__raytracing-renderer__scene_texture.json", options);
  ASSERT_FALSE(s.textures.empty());
  EXPECT_EQ(s.textures[0].kind, TEXTURE_CHECKER);
}

}  // namespace
}  // namespace caustica

// Benchmark scenes in the spirit of the seed report's Table 1 (BVH vs no BVH):
// "400_spheres", "1600_shapes", "6400_shapes", "12800_shapes". The report's
// files were never published, so these are reconstructions: a pinhole camera
// looking into a box of small random primitives above a ground, phong mode.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>

namespace caustica {

// A coursework-format phong scene (1200x800) with exactly `shape_count`
// shapes, the first being the ground (a large sphere). mixed=false: spheres
// only. mixed=true: the other shape_count-1 shapes are split into thirds,
// triangles = cylinders = (shape_count-1)/3 and spheres take the rest.
// The same (shape_count, mixed, seed) gives byte-identical JSON on every
// platform: own PRNG, coordinates rounded to 1e-4. Throws caustica::Error
// when shape_count < 1.
nlohmann::json generate_table1_scene(int shape_count, bool mixed, uint32_t seed);

// "400_spheres" / "1600_shapes": the report's names for these scenes.
std::string table1_scene_name(int shape_count, bool mixed);

}  // namespace caustica

// glTF documents built in memory for tests: one embedded base64 buffer,
// views, accessors, meshes and nodes added one call at a time, so every
// expected value of an import is known to the test that wrote it.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace caustica::test {

inline std::string base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < in.size(); i += 3) {
    uint32_t v = uint32_t(uint8_t(in[i])) << 16;
    if (i + 1 < in.size()) v |= uint32_t(uint8_t(in[i + 1])) << 8;
    if (i + 2 < in.size()) v |= uint32_t(uint8_t(in[i + 2]));
    out += k[v >> 18 & 63];
    out += k[v >> 12 & 63];
    out += i + 1 < in.size() ? k[v >> 6 & 63] : '=';
    out += i + 2 < in.size() ? k[v & 63] : '=';
  }
  return out;
}

// A glTF document under construction: one buffer, embedded.
struct Doc {
  nlohmann::json j = {{"asset", {{"version", "2.0"}}}};
  std::string bin;

  int view(const std::string& bytes, size_t stride = 0) {
    while (bin.size() % 4) bin += '\0';
    nlohmann::json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes.size()}};
    if (stride) v["byteStride"] = stride;
    bin += bytes;
    j["bufferViews"].push_back(v);
    return int(j["bufferViews"].size() - 1);
  }
  int accessor(int view, int component, size_t count, const char* type, size_t offset = 0) {
    j["accessors"].push_back({{"bufferView", view}, {"componentType", component}, {"count", count},
                              {"type", type}, {"byteOffset", offset}});
    return int(j["accessors"].size() - 1);
  }
  template <class T>
  static std::string bytes(const std::vector<T>& v) {
    return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  int floats(const std::vector<float>& v, const char* type, size_t components) {
    return accessor(view(bytes(v)), 5126, v.size() / components, type);
  }
  // A mesh of one primitive with these positions (and indices, mode).
  int mesh(const std::vector<float>& positions, const std::vector<uint16_t>& indices = {}, int mode = 4) {
    nlohmann::json prim = {{"attributes", {{"POSITION", floats(positions, "VEC3", 3)}}}, {"mode", mode}};
    if (!indices.empty()) prim["indices"] = accessor(view(bytes(indices)), 5123, indices.size(), "SCALAR");
    j["meshes"].push_back({{"primitives", {prim}}});
    return int(j["meshes"].size() - 1);
  }
  int node(nlohmann::json n) {
    j["nodes"].push_back(n);
    return int(j["nodes"].size() - 1);
  }
  std::string text(std::vector<int> roots = {0}) {
    if (!j.contains("scenes")) j["scenes"] = {{{"nodes", roots}}};
    j["buffers"] = {{{"byteLength", bin.size()},
                     {"uri", "data:application/octet-stream;base64," + base64(bin)}}};
    return j.dump();
  }
};

}  // namespace caustica::test

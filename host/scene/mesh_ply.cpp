// Stanford PLY (ascii / binary_little_endian / binary_big_endian 1.0). There
// is no Debian package for a PLY reader, and the files worth rendering are
// large scans (the armadillo is 346k faces), so the whole file is read into
// memory and binary values are decoded with memcpy + byte swaps.
//
// Only vertex x y z (plus nx ny nz and a texture-coordinate pair when all
// present) and the face index list are used; every other property, list or
// element is skipped by its declared size, wherever it appears. Scanner output
// such as the armadillo's puts a per-face "intensity" before the index list.
// Every value used must be finite in single precision (a NaN or infinite
// vertex fails the load, naming the item and, in ASCII files, the line), and
// no count is trusted before the bytes it needs are known to be there.
#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "host/error.h"
#include "host/limits.h"
#include "host/read_file.h"
#include "host/scene/mesh_internal.h"

namespace caustica::mesh_internal {

namespace {

enum class Type : uint8_t { I8, U8, I16, U16, I32, U32, F32, F64 };
enum class Format { Ascii, BinaryLE, BinaryBE };

struct Property {
  std::string name;
  Type type = Type::F32;  // the item type for a list
  bool is_list = false;
  Type count_type = Type::U8;
  int slot = -1;  // where the value goes (see Slot), -1: skipped
};

struct Element {
  std::string name;
  uint64_t count = 0;
  std::vector<Property> props;
};

// Destinations of per-vertex values; kIndices marks the face index list.
enum Slot { kX, kY, kZ, kNX, kNY, kNZ, kU, kV, kSlots, kIndices = 100 };

bool parse_type(const std::string& s, Type& t) {
  static const struct {
    const char* name;
    Type type;
  } names[] = {{"char", Type::I8},    {"int8", Type::I8},     {"uchar", Type::U8},  {"uint8", Type::U8},
               {"short", Type::I16},  {"int16", Type::I16},   {"ushort", Type::U16}, {"uint16", Type::U16},
               {"int", Type::I32},    {"int32", Type::I32},   {"uint", Type::U32},  {"uint32", Type::U32},
               {"float", Type::F32},  {"float32", Type::F32}, {"double", Type::F64}, {"float64", Type::F64}};
  for (const auto& n : names)
    if (s == n.name) {
      t = n.type;
      return true;
    }
  return false;
}

size_t type_size(Type t) {
  switch (t) {
    case Type::I8: case Type::U8: return 1;
    case Type::I16: case Type::U16: return 2;
    case Type::I32: case Type::U32: case Type::F32: return 4;
    case Type::F64: return 8;
  }
  return 0;
}

bool is_integer(Type t) { return t != Type::F32 && t != Type::F64; }

template <typename U>
U load_bits(const unsigned char* p, bool swap) {
  U u;
  std::memcpy(&u, p, sizeof(U));
  if (swap) {
    if constexpr (sizeof(U) == 2) u = __builtin_bswap16(u);
    if constexpr (sizeof(U) == 4) u = __builtin_bswap32(u);
    if constexpr (sizeof(U) == 8) u = __builtin_bswap64(u);
  }
  return u;
}

template <typename T, typename U>
T load(const unsigned char* p, bool swap) {
  const U u = load_bits<U>(p, swap);
  T v;
  std::memcpy(&v, &u, sizeof(T));
  return v;
}

// double holds every value of every PLY type exactly.
double read_binary(const unsigned char* p, Type t, bool swap) {
  switch (t) {
    case Type::I8: return static_cast<int8_t>(p[0]);
    case Type::U8: return p[0];
    case Type::I16: return load<int16_t, uint16_t>(p, swap);
    case Type::U16: return load<uint16_t, uint16_t>(p, swap);
    case Type::I32: return load<int32_t, uint32_t>(p, swap);
    case Type::U32: return load<uint32_t, uint32_t>(p, swap);
    case Type::F32: return load<float, uint32_t>(p, swap);
    case Type::F64: return load<double, uint64_t>(p, swap);
  }
  return 0.0;
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const size_t b = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > b) out.push_back(line.substr(b, i - b));
  }
  return out;
}

class PlyReader {
 public:
  PlyReader(const std::string& path, std::string data) : path_(path), data_(std::move(data)) {}

  Mesh read() {
    parse_header();
    const unsigned char* p = bytes() + body_;
    const unsigned char* end = bytes() + data_.size();
    for (const Element& e : elements_) {
      if (e.props.empty()) continue;  // nothing stored, however large the count
      if (format_ == Format::Ascii)
        read_ascii(e, p, end);
      else
        read_binary_element(e, p, end);
    }
    return build();
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { throw Error(path_ + ": " + what); }
  [[noreturn]] void header_fail(int line, const std::string& what) const {
    fail("PLY header line " + std::to_string(line) + ": " + what);
  }
  std::string item(const Element& e, uint64_t i) const {
    return "element '" + e.name + "' item " + std::to_string(i + 1) + " of " + std::to_string(e.count);
  }

  void parse_header();
  void assign_slots(Element& e);
  void read_binary_element(const Element& e, const unsigned char*& p, const unsigned char* end);
  void read_ascii(const Element& e, const unsigned char*& p, const unsigned char* end);
  void store(const Element& e, const float* v, uint64_t i, const std::string& line);
  // The vertex values in use (position, and normals / uvs when read).
  bool all_finite(const float* v) const {
    for (int k = 0; k < kSlots; ++k)
      if (!((k >= kNX && k <= kNZ && !normals_) || (k >= kU && !uvs_)) && !std::isfinite(v[k])) return false;
    return true;
  }
  Mesh build();

  const unsigned char* bytes() const { return reinterpret_cast<const unsigned char*>(data_.data()); }

  std::string path_;
  std::string data_;
  size_t body_ = 0;
  int header_lines_ = 0;
  Format format_ = Format::Ascii;
  std::vector<Element> elements_;
  const Element* vertex_ = nullptr;
  bool normals_ = false, uvs_ = false;

  std::vector<glm::vec3> positions_, normals_data_;
  std::vector<glm::vec2> uv_data_;
  std::vector<int64_t> corners_;      // face corners, all faces back to back
  std::vector<uint32_t> face_sizes_;  // corners per face
};

void PlyReader::parse_header() {
  size_t pos = 0;
  auto next_line = [&](std::string& line) {
    if (pos >= data_.size()) return false;
    const void* nl = std::memchr(bytes() + pos, '\n', data_.size() - pos);
    const size_t stop = nl ? static_cast<size_t>(static_cast<const unsigned char*>(nl) - bytes()) : data_.size();
    line.assign(data_.data() + pos, stop - pos);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    pos = stop + 1;
    ++header_lines_;
    return true;
  };

  std::string line;
  if (!next_line(line) || split(line) != std::vector<std::string>{"ply"})
    fail("not a PLY file (the first line is not 'ply')");
  bool have_format = false, ended = false;
  while (!ended && next_line(line)) {
    const int ln = header_lines_;
    const auto tok = split(line);
    if (tok.empty() || tok[0] == "comment" || tok[0] == "obj_info") continue;
    if (tok[0] == "format") {
      if (tok.size() != 3) header_fail(ln, "expected 'format <type> 1.0'");
      if (tok[1] == "ascii") format_ = Format::Ascii;
      else if (tok[1] == "binary_little_endian") format_ = Format::BinaryLE;
      else if (tok[1] == "binary_big_endian") format_ = Format::BinaryBE;
      else header_fail(ln, "unknown format '" + tok[1] + "' (expected ascii, binary_little_endian or binary_big_endian)");
      if (tok[2] != "1.0") header_fail(ln, "unsupported PLY version '" + tok[2] + "' (expected 1.0)");
      have_format = true;
    } else if (tok[0] == "element") {
      if (tok.size() != 3) header_fail(ln, "expected 'element <name> <count>'");
      Element e;
      e.name = tok[1];
      const char* b = tok[2].data();
      const auto r = std::from_chars(b, b + tok[2].size(), e.count);
      if (r.ec != std::errc() || r.ptr != b + tok[2].size()) header_fail(ln, "bad element count '" + tok[2] + "'");
      elements_.push_back(std::move(e));
    } else if (tok[0] == "property") {
      if (elements_.empty()) header_fail(ln, "property before any element");
      Property prop;
      const bool list = tok.size() >= 2 && tok[1] == "list";
      if (list ? tok.size() != 5 : tok.size() != 3)
        header_fail(ln, list ? "expected 'property list <count type> <item type> <name>'" : "expected 'property <type> <name>'");
      const std::string& type = list ? tok[3] : tok[1];
      if (!parse_type(type, prop.type)) header_fail(ln, "unknown property type '" + type + "'");
      if (list) {
        prop.is_list = true;
        if (!parse_type(tok[2], prop.count_type)) header_fail(ln, "unknown property type '" + tok[2] + "'");
        if (!is_integer(prop.count_type)) header_fail(ln, "list count type '" + tok[2] + "' is not an integer type");
      }
      prop.name = tok.back();
      elements_.back().props.push_back(std::move(prop));
    } else if (tok[0] == "end_header") {
      ended = true;
    } else {
      // Unknown lines are refused: a mistyped 'property' would silently shift every binary value after it.
      header_fail(ln, "unexpected '" + tok[0] + "'");
    }
  }
  if (!ended) fail("PLY header has no 'end_header' line");
  if (!have_format) fail("PLY header has no 'format' line");
  body_ = std::min(pos, data_.size());
  for (Element& e : elements_) assign_slots(e);
  if (!vertex_) fail("PLY file has no 'vertex' element");
}

void PlyReader::assign_slots(Element& e) {
  auto find = [&e](const char* name) -> Property* {
    for (Property& p : e.props)
      if (!p.is_list && p.name == name) return &p;
    return nullptr;
  };
  if (e.name == "vertex" && !vertex_) {
    vertex_ = &e;
    static const char* const xyz[] = {"x", "y", "z"};
    for (int k = 0; k < 3; ++k) {
      Property* p = find(xyz[k]);
      if (!p) fail("PLY element 'vertex' has no '" + std::string(xyz[k]) + "' property");
      p->slot = kX + k;
    }
    Property *nx = find("nx"), *ny = find("ny"), *nz = find("nz");
    normals_ = nx && ny && nz;
    if (normals_) nx->slot = kNX, ny->slot = kNY, nz->slot = kNZ;
    static const char* const uv_names[][2] = {{"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}, {"texture_s", "texture_t"}};
    for (const auto& names : uv_names) {
      Property *u = find(names[0]), *v = find(names[1]);
      if (u && v) {
        u->slot = kU, v->slot = kV;
        uvs_ = true;
        break;
      }
    }
  } else if (e.name == "face") {
    for (Property& p : e.props)
      if (p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index")) {
        if (!is_integer(p.type)) fail("PLY face list '" + p.name + "' has a non-integer index type");
        p.slot = kIndices;
        break;
      }
  }
}

void PlyReader::store(const Element& e, const float* v, uint64_t i, const std::string& line) {
  if (&e != vertex_) return;
  static const char* const names[kSlots] = {"x", "y", "z", "nx", "ny", "nz", "u", "v"};
  for (int k = 0; !all_finite(v) && k < kSlots; ++k) {
    if ((k >= kNX && k <= kNZ && !normals_) || (k >= kU && !uvs_)) continue;
    if (!std::isfinite(v[k]))
      fail("PLY " + item(e, i) + line + ": expected a finite '" + names[k] +
           "' (a number within single precision), got " + (std::isnan(v[k]) ? "nan" : v[k] > 0 ? "inf" : "-inf"));
  }
  positions_.emplace_back(v[kX], v[kY], v[kZ]);
  if (normals_) normals_data_.emplace_back(v[kNX], v[kNY], v[kNZ]);
  if (uvs_) uv_data_.emplace_back(v[kU], v[kV]);
}

void PlyReader::read_binary_element(const Element& e, const unsigned char*& p, const unsigned char* end) {
  static const bool host_big = [] {
    const uint16_t one = 1;
    unsigned char b;
    std::memcpy(&b, &one, 1);
    return b == 0;
  }();
  const bool swap = (format_ == Format::BinaryBE) != host_big;

  // The smallest possible item (empty lists) bounds the count before any
  // allocation: a corrupt count must give "truncated", not bad_alloc.
  size_t min_item = 0;
  for (const Property& prop : e.props) min_item += type_size(prop.is_list ? prop.count_type : prop.type);
  const size_t left = static_cast<size_t>(end - p);
  if (e.count > left / min_item)
    fail("truncated PLY data: element '" + e.name + "' declares " + std::to_string(e.count) + " items of at least " +
         std::to_string(min_item) + " bytes, but only " + std::to_string(left) + " bytes follow the header");
  if (&e == vertex_) {
    positions_.reserve(e.count);
    if (normals_) normals_data_.reserve(e.count);
    if (uvs_) uv_data_.reserve(e.count);
  }

  float v[kSlots] = {};
  for (uint64_t i = 0; i < e.count; ++i) {
    for (const Property& prop : e.props) {
      const size_t size = type_size(prop.type);
      if (!prop.is_list) {
        if (static_cast<size_t>(end - p) < size) fail("truncated PLY data in " + item(e, i));
        if (prop.slot >= 0) v[prop.slot] = static_cast<float>(read_binary(p, prop.type, swap));
        p += size;
        continue;
      }
      const size_t csize = type_size(prop.count_type);
      if (static_cast<size_t>(end - p) < csize) fail("truncated PLY data in " + item(e, i));
      const double count = read_binary(p, prop.count_type, swap);
      p += csize;
      if (count < 0) fail("PLY " + item(e, i) + " has a negative list length");
      const size_t n = static_cast<size_t>(count);
      if (n > static_cast<size_t>(end - p) / size) fail("truncated PLY data in " + item(e, i));
      if (prop.slot == kIndices) {
        face_sizes_.push_back(static_cast<uint32_t>(n));
        for (size_t k = 0; k < n; ++k) corners_.push_back(static_cast<int64_t>(read_binary(p + k * size, prop.type, swap)));
      }
      p += n * size;
    }
    store(e, v, i, "");
  }
}

void PlyReader::read_ascii(const Element& e, const unsigned char*& p, const unsigned char* end) {
  // One item per line, as every writer does it; holding to that turns a
  // missing or extra value into an error on the right line instead of a
  // silent shift of everything after it.
  auto line_of = [&](const unsigned char* at) {
    return std::to_string(header_lines_ + 1 +
                          std::count(static_cast<const unsigned char*>(bytes()) + body_, at, static_cast<unsigned char>('\n')));
  };
  auto skip_blanks = [&] {
    while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
  };
  uint64_t i = 0;
  auto value = [&]() -> double {
    skip_blanks();
    if (p == end || *p == '\n')
      fail("PLY " + item(e, i) + " (line " + line_of(p) + ") has fewer values than the header declares");
    const unsigned char* b = p;
    while (p < end && *p != ' ' && *p != '\t' && *p != '\r' && *p != '\n') ++p;
    const char* s = reinterpret_cast<const char*>(b);
    const char* t = reinterpret_cast<const char*>(p);
    if (*s == '+' && t - s > 1) ++s;
    double d = 0.0;
    const auto r = std::from_chars(s, t, d);
    if (r.ec != std::errc() || r.ptr != t)
      fail("PLY " + item(e, i) + " (line " + line_of(b) + "): '" + std::string(reinterpret_cast<const char*>(b), t) +
           "' is not a number");
    return d;
  };
  auto integer = [&]() -> double {
    const double d = value();
    // 2^53 keeps the later conversion to int64 defined; no real count or index comes near it.
    if (!std::isfinite(d) || d != std::floor(d) || std::fabs(d) > 9007199254740992.0)
      fail("PLY " + item(e, i) + " (line " + line_of(p) + "): expected an integer, got " + std::to_string(d));
    return d;
  };

  float v[kSlots] = {};
  for (; i < e.count; ++i) {
    while (p < end && (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n')) ++p;
    if (p == end) fail("truncated PLY data: the file ends before " + item(e, i));
    for (const Property& prop : e.props) {
      if (!prop.is_list) {
        const double d = is_integer(prop.type) ? integer() : value();
        if (prop.slot >= 0) v[prop.slot] = static_cast<float>(d);
        continue;
      }
      const double count = integer();
      if (count < 0) fail("PLY " + item(e, i) + " has a negative list length");
      const size_t n = static_cast<size_t>(count);
      if (prop.slot == kIndices) face_sizes_.push_back(static_cast<uint32_t>(n));
      for (size_t k = 0; k < n; ++k) {
        const double d = is_integer(prop.type) ? integer() : value();
        if (prop.slot == kIndices) corners_.push_back(static_cast<int64_t>(d));
      }
    }
    skip_blanks();
    if (p < end && *p != '\n')
      fail("PLY " + item(e, i) + " (line " + line_of(p) + ") has more values than the header declares");
    store(e, v, i, &e == vertex_ && !all_finite(v) ? " (line " + line_of(p) + ")" : "");
  }
}

Mesh PlyReader::build() {
  Mesh mesh;
  mesh.source_faces = face_sizes_.size();
  mesh.triangles.reserve(corners_.size() / 3);
  const int64_t nv = static_cast<int64_t>(positions_.size());
  std::vector<glm::vec3> pos;
  std::vector<uint32_t> tris;
  size_t offset = 0;
  for (size_t f = 0; f < face_sizes_.size(); ++f) {
    const int64_t* idx = corners_.data() + offset;
    const size_t n = face_sizes_[f];
    offset += n;
    for (size_t k = 0; k < n; ++k)
      if (idx[k] < 0 || idx[k] >= nv)
        fail("PLY face " + std::to_string(f) + " (counting from 0): vertex index " + std::to_string(idx[k]) +
             " is out of range (the file has " + std::to_string(nv) + " vertices)");
    if (n < 3) {
      ++mesh.dropped_degenerate;
      continue;
    }
    tris.clear();
    if (n == 3) {
      tris = {0, 1, 2};
    } else {
      pos.clear();
      for (size_t k = 0; k < n; ++k) pos.push_back(positions_[static_cast<size_t>(idx[k])]);
      triangulate_polygon(pos, tris);
    }
    for (size_t t = 0; t + 2 < tris.size(); t += 3) {
      glm::vec3 p[3], nrm[3];
      glm::vec2 uv[3];
      for (int k = 0; k < 3; ++k) {
        const size_t vi = static_cast<size_t>(idx[tris[t + k]]);
        p[k] = positions_[vi];
        if (normals_) nrm[k] = normals_data_[vi];
        if (uvs_) uv[k] = uv_data_[vi];
      }
      add_triangle(mesh, p, normals_ ? nrm : nullptr, uvs_ ? uv : nullptr, -1);
    }
  }
  return mesh;
}

}  // namespace

Mesh load_ply(const std::string& path) {
  return parse_ply(path, read_input_file(path, "PLY file", limits::kMaxMeshFileBytes));
}

Mesh parse_ply(const std::string& path, std::string data) { return PlyReader(path, std::move(data)).read(); }

}  // namespace caustica::mesh_internal

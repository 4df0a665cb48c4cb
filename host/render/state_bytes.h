// Bytes of render state files (host/render/render_state.h): little-endian
// numbers whatever the host, texts and arrays with their lengths, and
// blobs (raw bytes of device structs whose layout kernels/shared/ fixes and
// host/cl/layout_check.cpp asserts). A read past the end of what it was
// given throws caustica::Error naming the file and the field.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "host/error.h"

namespace caustica {

// Little-endian whatever the host (the file moves between machines).
class StateWriter {
 public:
  template <typename T>
  void put(T v) {
    static_assert(std::is_arithmetic_v<T>);
    uint64_t bits = 0;
    if constexpr (std::is_floating_point_v<T>) {
      using Bits = std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>;
      Bits b;
      std::memcpy(&b, &v, sizeof b);
      bits = b;
    } else {
      bits = uint64_t(v);
    }
    for (size_t i = 0; i < sizeof(T); ++i) bytes_.push_back(char((bits >> (8 * i)) & 0xFF));
  }
  void text(const std::string& s) {
    put(uint32_t(s.size()));
    bytes_ += s;
  }
  template <typename T>
  void array(const std::vector<T>& values) {
    put(uint64_t(values.size()));
    for (const T& v : values) put(v);
  }
  void blob(const std::string& bytes) {
    put(uint64_t(bytes.size()));
    bytes_ += bytes;
  }
  std::string& bytes() { return bytes_; }

 private:
  std::string bytes_;
};

class StateReader {
 public:
  StateReader(const std::string& bytes, size_t begin, size_t end, const std::string& path)
      : bytes_(bytes), at_(begin), end_(end), path_(path) {}
  template <typename T>
  T get(const char* what) {
    static_assert(std::is_arithmetic_v<T>);
    need(sizeof(T), what);
    uint64_t bits = 0;
    for (size_t i = 0; i < sizeof(T); ++i) bits |= uint64_t(static_cast<unsigned char>(bytes_[at_ + i])) << (8 * i);
    at_ += sizeof(T);
    if constexpr (std::is_floating_point_v<T>) {
      using Bits = std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>;
      const Bits b = Bits(bits);
      T v;
      std::memcpy(&v, &b, sizeof v);
      return v;
    } else {
      return T(bits);
    }
  }
  std::string text(const char* what) {
    const uint32_t n = get<uint32_t>(what);
    need(n, what);
    std::string s = bytes_.substr(at_, n);
    at_ += n;
    return s;
  }
  template <typename T>
  std::vector<T> array(const char* what) {
    const uint64_t n = get<uint64_t>(what);
    if (n > (end_ - at_) / sizeof(T)) fail(std::string(what) + " of " + std::to_string(n) + " values");
    std::vector<T> values(n);
    for (T& v : values) v = get<T>(what);
    return values;
  }
  std::string blob(const char* what) {
    const uint64_t n = get<uint64_t>(what);
    need(n, what);
    std::string s = bytes_.substr(at_, n);
    at_ += n;
    return s;
  }
  bool done() const { return at_ == end_; }

 private:
  void need(uint64_t n, const std::string& what) {
    if (n > end_ - at_) fail(what);
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw Error(path_ + ": the state's payload ends inside its " + what + " (written by another caustica?)");
  }
  const std::string& bytes_;
  size_t at_, end_;
  const std::string& path_;
};

}  // namespace caustica

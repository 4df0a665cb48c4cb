// One exception type for everything the user can get wrong or the platform
// can refuse: its message is printed as-is by main, so it must name the file,
// key or device involved and say what was expected.
#pragma once

#include <stdexcept>
#include <string>

namespace caustica {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace caustica

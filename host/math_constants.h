// Constants the host code shares (one definition each, so units can also
// be compiled together: CMAKE_UNITY_BUILD, docs/howto.md "Build and test time").
#pragma once

namespace caustica {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr float kPiF = float(kPi);  // the float nearest pi, M_PI_F's bits

}  // namespace caustica

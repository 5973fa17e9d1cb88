// tests/support/tonemap_reference.h — the tone mapping curves as their sources write them, in
// double precision, for tests that check mvr's (lighting.h finishColor) against them.
#pragma once

#include <algorithm>

#include <glm/glm.hpp>

namespace mvr::test {

/// Khronos PBR Neutral (KhronosGroup/ToneMapping, PBR_Neutral/README.md's reference function).
inline glm::dvec3 khrPbrNeutralReference(glm::dvec3 color) {
    const double startCompression = 0.8 - 0.04;
    const double desaturation = 0.15;
    const double x = std::min(color.x, std::min(color.y, color.z));
    const double offset = x < 0.08 ? x - 6.25 * x * x : 0.04;
    color -= offset;
    const double peak = std::max(color.x, std::max(color.y, color.z));
    if (peak < startCompression) return color;
    const double d = 1.0 - startCompression;
    const double newPeak = 1.0 - d * d / (peak + d - startCompression);
    color *= newPeak / peak;
    const double g = 1.0 - 1.0 / (desaturation * (peak - newPeak) + 1.0);
    return glm::mix(color, glm::dvec3(newPeak), g);
}

/// Narkowicz's ACES filmic fit (2016, "ACES Filmic Tone Mapping Curve"), clamped to [0, 1].
inline glm::dvec3 acesNarkowiczReference(glm::dvec3 x) {
    const double a = 2.51, b = 0.03, c = 2.43, d = 0.59, e = 0.14;
    return glm::clamp((x * (a * x + b)) / (x * (c * x + d) + e), 0.0, 1.0);
}

}  // namespace mvr::test

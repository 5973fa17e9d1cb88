#include "mvr/composite/anaglyph.h"

#include <algorithm>
#include <cmath>

#include <fmt/core.h>

#include "mvr/composite/layout.h"

namespace mvr::composite {
namespace {

constexpr float kY0 = 0.2126f, kY1 = 0.7152f, kY2 = 0.0722f;

// Dubois' matrices, from E. Dubois, "Conversion of a Stereo Pair to Anaglyph with the
// Least-Squares Projection Method" (University of Ottawa, March 2009; the revised values on
// his page www.site.uottawa.ca/~edubois/anaglyph/, computed for typical LCD primaries and the
// measured transmission of the respective glasses). They act on linear RGB. The red-cyan set
// is the 2009 one (first row 0.437 0.449 0.164); the older 0.456 0.500 0.176 set is from his
// ICASSP 2001 paper and is not used here.
const AnaglyphMatrices kMatrices[] = {
    // Color
    {{1, 0, 0, 0, 0, 0, 0, 0, 0}, {0, 0, 0, 0, 1, 0, 0, 0, 1}},
    // HalfColor
    {{kY0, kY1, kY2, 0, 0, 0, 0, 0, 0}, {0, 0, 0, 0, 1, 0, 0, 0, 1}},
    // Gray
    {{kY0, kY1, kY2, 0, 0, 0, 0, 0, 0}, {0, 0, 0, kY0, kY1, kY2, kY0, kY1, kY2}},
    // True
    {{kY0, kY1, kY2, 0, 0, 0, 0, 0, 0}, {0, 0, 0, 0, 0, 0, kY0, kY1, kY2}},
    // Dubois red-cyan
    {{0.437f, 0.449f, 0.164f, -0.062f, -0.062f, -0.024f, -0.048f, -0.050f, -0.017f},
     {-0.011f, -0.032f, -0.007f, 0.377f, 0.761f, 0.009f, -0.026f, -0.093f, 1.234f}},
    // Dubois green-magenta
    {{-0.062f, -0.158f, -0.039f, 0.284f, 0.668f, 0.143f, -0.015f, -0.027f, 0.021f},
     {0.529f, 0.705f, 0.024f, -0.016f, -0.015f, -0.065f, 0.009f, 0.075f, 0.937f}},
    // Dubois amber-blue
    {{1.062f, -0.205f, 0.299f, -0.026f, 0.908f, 0.068f, -0.038f, -0.173f, 0.022f},
     {-0.016f, -0.123f, -0.017f, 0.006f, 0.062f, -0.017f, 0.094f, 0.185f, 0.911f}},
};

// decode: the 256 linear values of the 8-bit codes. encode: round(linearToSrgb(l) · 255) is
// the number of codes k ≥ 1 whose lower rounding edge srgbToLinear((k − 0.5) / 255) is ≤ l,
// because the sRGB curve is monotonic — a binary search over 255 edges instead of a pow() per
// channel (10× faster; equal to the direct formula except where float rounding of the two
// forms lands on opposite sides of an edge, i.e. within rounding).
struct Tables {
    float decode[256];
    float edge[255];
    Tables() {
        for (int i = 0; i < 256; ++i) decode[i] = srgbToLinear(static_cast<float>(i) / 255.0f);
        for (int k = 1; k < 256; ++k) edge[k - 1] = srgbToLinear((static_cast<float>(k) - 0.5f) / 255.0f);
    }
};

const Tables& tables() {
    static const Tables t;
    return t;
}

std::uint8_t encode8(const Tables& t, float linear) {
    return static_cast<std::uint8_t>(std::upper_bound(t.edge, t.edge + 255, linear) - t.edge);
}

Rgba8 mix(const AnaglyphMatrices& m, const Tables& tab, Rgba8 left, Rgba8 right) {
    const float* t = tab.decode;
    const float l[3] = {t[left.r], t[left.g], t[left.b]};
    const float r[3] = {t[right.r], t[right.g], t[right.b]};
    float o[3];
    for (int row = 0; row < 3; ++row) {
        const float* ml = &m.left[row * 3];
        const float* mr = &m.right[row * 3];
        o[row] = ml[0] * l[0] + ml[1] * l[1] + ml[2] * l[2] + mr[0] * r[0] + mr[1] * r[1] +
                 mr[2] * r[2];
    }
    return {encode8(tab, o[0]), encode8(tab, o[1]), encode8(tab, o[2]), 255};
}

}  // namespace

const AnaglyphMatrices& anaglyphMatrices(AnaglyphMethod method) {
    return kMatrices[static_cast<int>(method)];
}

float srgbToLinear(float c) {
    c = std::clamp(c, 0.0f, 1.0f);
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

float linearToSrgb(float c) {
    c = std::clamp(c, 0.0f, 1.0f);
    return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

Rgba8 anaglyphPixel(const AnaglyphMatrices& m, Rgba8 left, Rgba8 right) {
    return mix(m, tables(), left, right);
}

Result<Image> anaglyph(const Image& left, const Image& right, AnaglyphMethod method) {
    if (Status s = validatePair(left, right, "mvr::composite::anaglyph()"); !s) return s;
    const AnaglyphMatrices& m = anaglyphMatrices(method);
    const Tables& t = tables();
    Image out(left.width, left.height);
    const std::size_t n = static_cast<std::size_t>(left.width) * left.height;
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint8_t* a = &left.rgba[i * 4];
        const std::uint8_t* b = &right.rgba[i * 4];
        const Rgba8 c = mix(m, t, {a[0], a[1], a[2], a[3]}, {b[0], b[1], b[2], b[3]});
        std::uint8_t* o = &out.rgba[i * 4];
        o[0] = c.r;
        o[1] = c.g;
        o[2] = c.b;
        o[3] = 255;
    }
    return out;
}

}  // namespace mvr::composite

// mvr/composite/anaglyph.h — anaglyphs: two views mixed into one color image for colored
// glasses, computed in linear light.
//
// Per pixel (this is the exact math the GPU composite must mirror):
//
//     l = srgbToLinear(left.rgb / 255)          r = srgbToLinear(right.rgb / 255)
//     o = clamp(ML · l + MR · r, 0, 1)          (ML, MR: 3×3, row-major, per method)
//     out.rgb = round(linearToSrgb(o) · 255)    out.a = 255
//
// i.e. decode sRGB (IEC 61966-2-1 piecewise curve), mix, clamp, encode, round to nearest.
// The view images are treated as sRGB-encoded display values, which is how they are shown.
//
// Matrices (out.r, out.g, out.b rows; columns are the input r, g, b of that eye):
//   color       ML = [1 0 0; 0 0 0; 0 0 0]     MR = [0 0 0; 0 1 0; 0 0 1]
//   half-color  ML = [Y; 0; 0]                 MR = [0 0 0; 0 1 0; 0 0 1]
//   gray        ML = [Y; 0; 0]                 MR = [0; Y; Y]
//   true        ML = [Y; 0; 0]                 MR = [0; 0; Y]        (red-blue glasses)
//   with Y = (0.2126, 0.7152, 0.0722), the luminance of linear sRGB/Rec.709 primaries (the
//   familiar 0.299/0.587/0.114 are luma weights for gamma-encoded NTSC values and do not
//   belong in linear light).
//   dubois, dubois-gm, dubois-ab: Eric Dubois' least-squares projection matrices, see
//   anaglyph.cpp for the values and the source.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "mvr/core/image.h"
#include "mvr/core/status.h"

namespace mvr::composite {

enum class AnaglyphMethod {
    Color,               ///< red-cyan, left red channel + right green/blue
    HalfColor,           ///< red-cyan, left luminance in red (less retinal rivalry)
    Gray,                ///< red-cyan, luminance only
    True,                ///< red-blue, luminance (the classic "true anaglyph")
    Dubois,              ///< red-cyan, Dubois least squares
    DuboisGreenMagenta,  ///< green (left) - magenta (right), Dubois least squares
    DuboisAmberBlue,     ///< amber (left) - blue (right), Dubois least squares (ColorCode 3-D)
};

/// The two 3×3 mixing matrices of a method, row-major (out = left · l + right · r).
struct AnaglyphMatrices {
    std::array<float, 9> left;
    std::array<float, 9> right;
};

/// The method of an anaglyph format name ("anaglyph-dubois" → Dubois, …); nullopt for any
/// other name.
std::optional<AnaglyphMethod> anaglyphMethod(std::string_view format);
/// The format name of `method` ("anaglyph-dubois", …).
std::string_view anaglyphFormatName(AnaglyphMethod method);

/// Matrices of `method`. Never fails.
const AnaglyphMatrices& anaglyphMatrices(AnaglyphMethod method);

/// sRGB decode of an encoded value in [0, 1] (IEC 61966-2-1): c ≤ 0.04045 ? c / 12.92 :
/// ((c + 0.055) / 1.055)^2.4.
float srgbToLinear(float encoded);
/// sRGB encode of a linear value in [0, 1] (clamped first): c ≤ 0.0031308 ? 12.92 c :
/// 1.055 c^(1/2.4) − 0.055.
float linearToSrgb(float linear);

/// One anaglyph pixel (alpha 255) by the formula above.
Rgba8 anaglyphPixel(const AnaglyphMatrices& m, Rgba8 left, Rgba8 right);

/// GLSL (#version 330+) source of `vec3 mvrAnaglyph(vec3 left, vec3 right)` and its sRGB helpers
/// for `method`, generated from the same matrices (written column-major, as GLSL's mat3
/// constructor wants them), so a GPU composite computes exactly the formula above. Inputs are
/// the 8-bit-encoded values as a texture returns them from an RGBA8 (not sRGB) texture; the
/// result is written to an RGBA8 target (GL rounds to nearest).
std::string anaglyphGlsl(AnaglyphMethod method);

/// Whole-image anaglyph. Precondition (checked): same non-empty size. Errors: Usage.
Result<Image> anaglyph(const Image& left, const Image& right, AnaglyphMethod method);

}  // namespace mvr::composite

// mvr/composite/layout.h — formats that only rearrange pixels: side by side, top-bottom,
// row / column interleave, checkerboard, HDMI 1.4a frame packing, Looking-Glass quilt.
//
// Conventions as in compose.h: row 0 at the top, view 0 = leftmost eye = left image. Pixels
// are copied with their alpha; blank areas are opaque black. "Half" formats squeeze a view
// 2:1 by averaging each pair of pixels in the encoded values, rounding half up:
// out = (a + b + 1) / 2 per channel (what a bilinear texture fetch between two texel
// centres gives, so the GPU composite matches exactly up to its rounding).
// Every function validates its inputs and returns ErrorCode::Usage naming the function, the
// value and the expectation.
#pragma once

#include <span>

#include "mvr/core/image.h"
#include "mvr/core/status.h"

namespace mvr::composite {

/// Checks that `views` holds minViews..maxViews non-empty images of one size.
/// `who` names the caller in the message, e.g. "mvr::composite::compose(): sbs".
Status validateViews(std::span<const Image> views, int minViews, int maxViews, const char* who);
/// Checks that `a` and `b` are non-empty and of one size.
Status validatePair(const Image& a, const Image& b, const char* who);

/// `first` on the left, `second` on the right: 2W×H (full) or W×H (half: each squeezed to
/// W/2 columns; W must be even).
Result<Image> sideBySide(const Image& first, const Image& second, bool half);

/// `top` above `bottom`: W×2H (full) or W×H (half: each squeezed to H/2 rows; H even).
Result<Image> topBottom(const Image& top, const Image& bottom, bool half);

/// W×H, row y from views[y mod N] (row 0 — the top row — from view 0). N ≥ 2.
Result<Image> interleaveRows(std::span<const Image> views);

/// W×H, column x from views[x mod N] (column 0 from view 0). N = 2 is kalaiah2007's two-view
/// parallax-barrier interlace: the paper's odd columns (1-based, i.e. x = 0, 2, …) from the
/// left image and its even columns from the right image.
Result<Image> interleaveColumns(std::span<const Image> views);

/// W×H, pixel (x, y) from `first` where x + y is even, else from `second`.
Result<Image> checkerboard(const Image& first, const Image& second);

/// HDMI 1.4a 3D frame packing (progressive): left frame on top, then the active-space gap of
/// blank lines, then the right frame: 1280×720 → 1280×1470 (30 lines), 1920×1080 → 1920×2205
/// (45 lines). Errors: Usage for any other view size, naming the two allowed ones.
Result<Image> hdmiFramePacking(const Image& left, const Image& right);

/// Number of blank lines HDMI 1.4a frame packing puts between the frames of a view of
/// `height` lines: 30 for 720, 45 for 1080, -1 for a height it does not define.
int hdmiActiveSpaceLines(int width, int height);

/// Looking Glass quilt: `columns`×`rows` tiles of W×H, view i in tile column i mod C and tile
/// row ⌊i / C⌋ counted from the BOTTOM (view 0 bottom left, view C·R−1 top right); tiles
/// beyond N are black. Output (C·W)×(R·H). Errors: Usage when N > C·R or C, R < 1.
Result<Image> quilt(std::span<const Image> views, int columns, int rows);

}  // namespace mvr::composite

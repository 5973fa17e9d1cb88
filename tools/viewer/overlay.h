// tools/viewer/overlay.h — 2D elements drawn into each eye's image on the CPU: HUD text at
// screen depth and the 3D cursor (nvidia-gtc2010 "2D Objects", "Selection, Pointing in S3D").
//
// Why into the view images: the HUD and the cursor are drawn into every eye's image BEFORE the
// output format is composed, so every format (anaglyphs, side-by-side, half formats,
// interleaves, quad-buffer) carries them exactly as it carries the scene. A HUD element drawn at
// the same pixel position in both eyes has zero parallax: it sits on the screen (the
// convergence plane), "with no stereo projection". The 3D cursor is drawn in each eye at the
// position its 3D point projects to in that eye, so it has the parallax of the surface under
// the mouse and sits on it.
//
// Coordinates: image pixels, row 0 at the top (image.h), x to the right. Text is the library's
// (mvr/core/stereo_surfaces.h: 2D at depth, here at the screen's depth), that is
// stb_easy_font's (public domain, Sean Barrett): a 6×7 pixel font at scale 1, drawn as
// axis-aligned rectangles.
#pragma once

#include <string>
#include <string_view>

#include <glm/glm.hpp>

#include "mvr/core/image.h"

namespace mvr::viewer {

/// Text metrics at `scale` (integer pixel scale ≥ 1): width of the longest line and height of
/// all lines of `text` ('\n' separates lines), in pixels.
glm::ivec2 textSize(std::string_view text, int scale);

/// Draws `text` with its top-left corner at (x, y), in `color`, `scale`× magnified. Pixels
/// outside the image are skipped. Alpha of the image is left as is.
void drawText(Image& image, int x, int y, std::string_view text, Rgba8 color, int scale);

/// Darkens the rectangle [x0, x1) × [y0, y1) (clipped to the image) to `keep` of its value
/// (0 = black, 1 = unchanged): the backdrop that keeps HUD text readable on any scene.
void darkenRect(Image& image, int x0, int y0, int x1, int y1, float keep);

/// Draws a crosshair centred on the continuous position `center` (pixel centres at +0.5): four
/// arms of `arm` pixels around a gap, 2 pixels wide in `color` with a 1-pixel dark outline.
/// `center` snaps to the pixel it falls in, so the two eyes' crosshairs differ by the
/// parallax rounded to whole pixels (within one pixel of the exact disparity).
void drawCrosshair(Image& image, glm::vec2 center, int arm, Rgba8 color);

}  // namespace mvr::viewer

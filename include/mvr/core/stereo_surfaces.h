// mvr/core/stereo_surfaces.h — what is drawn into every view after the scene, with each view's
// stereo projection (nvidia-gtc2010 "Pseudo 3D objects", "2D Objects", "3D Objects Culling",
// "Letterbox"): the sky at infinity, the floating window, the letterbox bands and 2D elements
// (text, sprites) at a depth or at a 3D anchor point.
//
// Every function works on any backend's RenderOutput (one color and one depth image per view,
// rig view order; image.h conventions: row 0 at the top, window depth in [0, 1], 1 = cleared)
// and the Rig it was rendered with, so every backend and method gets the same surfaces. The
// ones that need a depth buffer (sky: its background key; floating window: the nearest depth at
// the frame edges; letterbox: its z test) refuse an output without one (RenderOutput::depth
// empty, e.g. gl gs-mrt) with ErrorCode::Unsupported naming the feature and the method; 2D
// elements are drawn without a depth test there.
//
// Order when several are asked for (applyStereoSurfaces): sky, angular anti-aliasing
// (angular_aa.h), labels, letterbox, floating window — the window's mask is last so that
// nothing is drawn over it.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "mvr/core/image.h"
#include "mvr/core/render.h"
#include "mvr/core/rig.h"
#include "mvr/core/status.h"

namespace mvr {

// ---- sky at infinity --------------------------------------------------------------------------

/// A sky: a color for every world direction. Kinds:
///  - Gradient: zenith → horizon → ground by the direction's elevation (world +Y up).
///  - Equirect: an equirectangular image (width = 2 · height): column u = 0.5 + lon / 2π with
///    lon = atan2(d.x, −d.z) (the image's centre column looks down −Z, mvr's default view
///    direction; +X to its right), row v = 0.5 − asin(d.y) / π (top row = straight up).
///  - CubeCross: a horizontal cross of six square faces (width:height = 4:3, face side s):
///          [ +Y ]
///    [ −X ][ −Z ][ +X ][ +Z ]
///          [ −Y ]
///    as unfolded around a viewer inside the cube looking down −Z with +Y up (−Z in the middle;
///    every face seen from inside, upright; +Y's bottom edge and −Y's top edge touch −Z).
/// Sampling is bilinear (equirect wraps around in longitude; cube faces clamp at their edges).
struct Sky {
    enum class Kind { Gradient, Equirect, CubeCross };
    Kind kind = Kind::Gradient;
    Image image;  ///< Equirect, CubeCross
    glm::vec3 zenith{0.16f, 0.36f, 0.80f}, horizon{0.72f, 0.84f, 0.98f},
        ground{0.30f, 0.27f, 0.24f};
};

/// loadSky() (a sky from "gradient" or a PNG / JPEG file) is in mvr/core/scene_io.h (library
/// mvr::scene_io): it decodes through mvr's PNG and JPEG readers, as textures do.

/// Where a direction (any length > 0) meets a CubeCross map: the face's column and row in the
/// cross (face side units) and the point on the face, u right and v down, in [−1, 1]. Shared
/// by the sky and the environment maps (mvr::io's loadEnvironmentMap).
struct CubeCrossPoint {
    int col = 1, row = 1;
    float u = 0.0f, v = 0.0f;
};
CubeCrossPoint cubeCrossPoint(glm::vec3 dir);

/// The sky's color (linear [0, 1]) in world direction `dir` (any length > 0).
glm::vec3 skyColor(const Sky& sky, glm::vec3 dir);

/// The world direction of the ray of `view` through the continuous pixel position `pixel`
/// (pixel centres at +0.5, row 0 at the top) of a width × height image: the view's inverse
/// projection, off-axis shear included, of the pixel at the far plane, minus the eye.
glm::vec3 viewRayDirection(const View& view, glm::vec2 pixel, int width, int height);

/// Paints every background pixel (depth ≥ 1, nothing drawn) of every view with the sky color
/// of that view's ray through the pixel: the sky is at infinity, so between two views its
/// parallax is the separation (rig.h), the far limit. Depth stays 1. Errors: sizes mismatch.
Status drawSky(const Sky& sky, const Rig& rig, std::vector<Image>& color,
               const std::vector<DepthImage>& depth);

// ---- floating window and letterbox ------------------------------------------------------------

/// The eye-space distance w (clip.w) of window depth `depth` in `view` (its projection's
/// z row; the same for every view of an off-axis rig).
float eyeDistance(const View& view, float depth);
/// The window depth of eye-space distance `w` in `view`.
float windowDepth(const View& view, float w);

/// The floating window of one view: how many columns are masked at its left and right edge,
/// and the distance that decided each (0 where nothing is cut).
struct WindowStrips {
    int left = 0, right = 0;
    float nearestLeft = 0.0f, nearestRight = 0.0f;
};

/// The strips, per view, of an off-axis rig's output. For view i with clip shear s_i (rig.h:
/// o_i / a) in a row whose shears span [s_min, s_max], a point at distance w < convergence C
/// that view i sees within
///     L_i(w) = W · (s_max − s_i) / 2 · (C / w − 1)   pixels of its left edge
///     R_i(w) = W · (s_i − s_min) / 2 · (C / w − 1)   pixels of its right edge
/// is outside the frustum of the rightmost (leftmost) view: cut by the frame in one eye only
/// (for a pair, L = R = W · separation · (C/w − 1) = −parallax in pixels: left eye's left edge,
/// right eye's right edge). The strip is the floating window moved forward to the nearest such
/// point: w_min = the nearest distance among the pixels (x, y) with x + ½ < L_i(w) (resp.
/// W − x − ½ < R_i(w)), and the strip is the columns whose centre lies inside L_i(w_min):
/// ceil(L_i(w_min) − ½). Nothing nearer than the screen at an edge: no strip. Errors:
/// Unsupported for views without a clip shear (toe-in, parallel, list rigs), sizes mismatch.
Result<std::vector<WindowStrips>> floatingWindowStrips(const Rig& rig,
                                                       const std::vector<DepthImage>& depth);

/// Blacks out the strips (nvidia-gtc2010: "Blacking out pixels in this area is better");
/// returns them.
Result<std::vector<WindowStrips>> applyFloatingWindow(const Rig& rig, std::vector<Image>& color,
                                                      const std::vector<DepthImage>& depth);

/// The rows of one letterbox band: round(percent / 100 · height), at the top and the bottom.
int letterboxRows(int height, float percent);

/// Two black horizontal bands, each `percent` (0 < percent < 50) of the height, drawn at the
/// convergence depth of each view: a band pixel is painted (and its depth set to the
/// convergence depth) only where the scene there is behind the screen, so out-of-screen
/// objects overdraw the bands. Errors: Usage for percent outside (0, 50), sizes mismatch.
Status drawLetterbox(const Rig& rig, std::vector<Image>& color, std::vector<DepthImage>& depth,
                     float percent);

// ---- 2D at depth ------------------------------------------------------------------------------

/// Text metrics of stb_easy_font (public domain, 6×7 pixel glyphs at scale 1): width of the
/// longest line and height of all lines ('\n' separates lines), in pixels at integer `scale`.
glm::ivec2 textSize(std::string_view text, int scale);

/// Draws `text` with its top-left corner at pixel (x, y) in `color`, `scale`× magnified,
/// clipped to the image. With `depth` (same size): only where `textDepth` ≤ the stored depth
/// (the scene in front hides it); depth is not written. Alpha is left as is.
void drawText(Image& image, int x, int y, std::string_view text, Rgba8 color, int scale,
              const DepthImage* depth = nullptr, float textDepth = 0.0f);

/// Draws an RGBA sprite (alpha > 0 pixels only, alpha-blended) with its top-left corner at
/// (x, y); with `depth`, depth-tested as drawText.
void drawSprite(Image& image, int x, int y, const Image& sprite, const DepthImage* depth = nullptr,
                float spriteDepth = 0.0f);

/// A 2D element placed in 3D: text (or a sprite when `sprite` is not empty), centred on its
/// point in every view. The point is either `anchor` (a world point: nvidia-gtc2010's "2D
/// object in depth attached to 3D anchor point") or the point on the mono camera's ray through
/// `screen` (fractions of the view, (0, 0) = top left) at eye-space distance `distance`
/// (≤ 0: the convergence distance, on the screen: zero parallax, where a HUD belongs).
struct Label {
    std::string text;
    Image sprite;
    std::optional<glm::vec3> anchor;
    glm::vec2 screen{0.5f, 0.5f};
    float distance = 0.0f;
    Rgba8 color{255, 255, 255, 255};
    int scale = 2;
};

/// The world point of a label (the anchor, or nvidia-gtc2010's 2D-to-3D conversion:
/// clip = (ndc.xy · w, ·, w) of the mono camera, unprojected).
glm::vec3 labelPoint(const Rig& rig, const Label& label);

/// Where world point `p` lands in a width × height image of `view`: pixel position (x, y,
/// continuous, row 0 at the top) and window depth (z). Nullopt behind the eye.
std::optional<glm::vec3> projectToPixel(const View& view, glm::vec3 p, int width, int height);

/// Draws every label into every view at the pixel its point projects to there (so its
/// parallax between views is that of its depth: separation · (1 − C / w) of the screen width),
/// depth-tested when `depth` holds one image per view. Errors: sizes mismatch.
Status drawLabels(const Rig& rig, const std::vector<Label>& labels, std::vector<Image>& color,
                  const std::vector<DepthImage>& depth);

/// Parses a label as the command line gives it: "TEXT@x,y[,distance]" (screen fractions and an
/// optional eye-space distance; the last '@' splits) or, with `anchored`, "TEXT@X,Y,Z" (a world
/// point). Errors: Usage quoting the text.
Result<Label> parseLabel(const std::string& spec, bool anchored);

// ---- all of them ------------------------------------------------------------------------------

/// What to draw after the scene (the CLI's --sky, --floating-window, --letterbox, --label).
struct StereoSurfaces {
    /// --background transparent: where nothing was drawn (depth 1) the views' alpha is 0, so
    /// their PNGs (and the composites laid out from them) are transparent there. First, before
    /// anything else is drawn; not with the surfaces that paint the background.
    bool transparentBackground = false;
    std::optional<Sky> sky;
    /// Angular anti-aliasing's scale S (angular_aa.h; --angular-aa); 0: off. After the sky (so
    /// that far silhouettes blend with it), before the labels, letterbox and window, which are
    /// drawn at their own depth, sharp.
    float angularAA = 0.0f;
    /// --angular-aa auto: skipped, not refused, on an output without depth (gl gs-mrt).
    bool angularAAOptional = false;
    /// The whole rig's clip shears, where the neighbours of a view are looked up (a view range
    /// or a rank renders some of its views); empty: the rendered rig's (angular_aa.h).
    std::vector<glm::vec2> angularAAShears;
    bool floatingWindow = false;
    float letterboxPercent = 0.0f;  ///< 0: none
    std::vector<Label> labels;
    bool any() const {
        return transparentBackground || sky || angularAA > 0.0f || floatingWindow ||
               letterboxPercent > 0.0f || !labels.empty();
    }
};

/// Applies them to `out` in the order above. Errors: Unsupported when a feature needing depth
/// meets an output without it ("--sky needs a depth buffer; method gs-mrt returns none").
Result<std::vector<WindowStrips>> applyStereoSurfaces(const StereoSurfaces& surfaces,
                                                      const Rig& rig, RenderOutput& out);

}  // namespace mvr

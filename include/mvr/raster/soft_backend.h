// mvr/raster/soft_backend.h — `soft`: mvr's own CPU rasterizer, the reference for every method.
//
// Conventions (the same as the GL backend, so that images compare pixel for pixel):
//  - Clip space as OpenGL: NDC = clip.xyz / clip.w, x and y in [−1, 1], z in [−1, 1] near→far.
//    Triangles are clipped in homogeneous space against the near and far planes (z = ±w) and a
//    guard band |x|, |y| ≤ 64·w; the viewport scissors the rest.
//  - Window coordinates: x_w = (ndc.x/2 + 1/2)·width, y_w = (ndc.y/2 + 1/2)·height, y UP; the
//    output images are flipped so that row 0 is the top (image.h). Pixel centers at
//    (x + 0.5, y + 0.5).
//  - Vertices snap to 1/256 pixel (8 sub-pixel bits; window coordinates fit a 24.8 int32 inside
//    the guard band; edge functions are evaluated exactly in int64). Fill rule: top-left (a pixel
//    center exactly on an edge is covered only by a top or left edge), so triangles that share an
//    edge cover each pixel once.
//  - Front faces are counter-clockwise. Culling (RenderSettings::cullBackFaces) uses the sign of
//    the homogeneous determinant det[x, y, w] of the triangle's clip positions (Olano & Greer),
//    which for off-axis rigs is evaluated in adelson1991's stereo form (see unified.cpp).
//  - Depth: window depth z_w = ndc.z/2 + 1/2 in [0, 1], interpolated linearly in screen space,
//    test LESS, cleared to 1. Colors and other attributes are interpolated perspective-correctly.
//  - Shading is lighting.h's model (Flat / Vertex / Pixel), view vector to Rig::centerEye().
//
// Methods:
//  - "multipass": N independent single-view renders (vertex shading, transform, clip, setup and
//    raster per view). Simple and exact; the ground truth.
//  - "unified": kalaiah2007's unified pipeline with adelson1991's simultaneous algorithms: vertex
//    work once, per-view positions by a clip-space shear, primitives replicated with a view tag,
//    back-face / clip / y setup shared by the views that share y, per-view depth and color.
//    Produces the same pixels as "multipass", bit for bit.
//
// Both methods run on a pool of worker threads pinned to the machine's cores; they split the
// views' images into horizontal bands (screen tiles spanning every view).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "mvr/core/render.h"

namespace mvr::raster {

/// Which SIMD code path the soft backend's kernels use.
enum class SimdPath { Auto, Scalar, Avx2, Avx512 };

struct SoftOptions {
    int threads = 0;                 ///< worker threads; 0 = one per core the process may use
    SimdPath simd = SimdPath::Auto;  ///< Auto: the best the CPU has and this build compiled
    /// unified and multipass: a frame whose images (8 bytes a pixel a view) are larger than this
    /// is drawn band by band into a scratch that stays in the workers' caches and streamed into
    /// the images (non-temporal stores); smaller frames are drawn into the images (each band's
    /// rows cleared just before). 0: always stream. (4 MiB: streaming was as fast for a pair of 420x560 and
    /// 256x256, faster from 4 views of 420x560 and a pair of 1024x768 on; src/raster/README.md.)
    std::size_t streamAboveBytes = std::size_t(4) << 20;
};

/// Finished image rows of every view, handed over band by band in place of the views' images
/// (RowStreamingBackend::renderRows): rows firstRow..lastRow (top first, inclusive) of each view.
struct ViewRows {
    int firstRow = 0, lastRow = 0;
    int width = 0;  ///< pixels a row
    /// Per view: its row firstRow, `width` RGBA8 pixels, the next rows after it.
    std::span<const std::uint8_t* const> first;
    const std::uint8_t* row(int view, int r) const {
        return first[std::size_t(view)] + std::size_t(r - firstRow) * std::size_t(width) * 4;
    }
};

/// Where RowStreamingBackend::renderRows() hands the rows: called from the backend's worker
/// threads, concurrently, each call for other rows; each row of every view comes exactly once.
class ViewRowSink {
public:
    virtual ~ViewRowSink() = default;
    virtual void rows(const ViewRows& rows) = 0;
};

/// A backend that can hand its views' rows over as they are finished, so that a composite is
/// made without the views' images in memory (the soft backend's "unified" method: its bands are
/// drawn into a per-worker scratch of every view's rows; direct lenticular rendering).
class RowStreamingBackend {
public:
    virtual ~RowStreamingBackend() = default;
    /// Renders as Backend::renderInto() does (one sample a pixel, colour only) and gives every
    /// row of every view to `sink`; nothing else is kept. Errors: as renderInto()'s, and
    /// Unsupported for a method that does not stream every view's rows at once (multipass) or
    /// a rig of one view, and for settings.samples > 1.
    virtual Status renderRows(const Scene& scene, const Rig& rig, const RenderSettings& settings,
                              const std::string& method, ViewRowSink& sink) = 0;
};

/// "scalar" | "avx2" | "avx512".
const char* simdPathName(SimdPath path);

/// The best SIMD path that both this build and this CPU support (never Auto).
SimdPath bestSimdPath();

/// Creates the soft backend (name "soft", methods "multipass" and "unified").
/// A requested SIMD path that the CPU or build lacks falls back to the best available one
/// (info() says which path runs).
std::unique_ptr<Backend> makeSoftBackend(const SoftOptions& options = {});

}  // namespace mvr::raster

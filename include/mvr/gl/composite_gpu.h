// mvr/gl/composite_gpu.h — every image format of the composite module, composed on the GPU: the
// one GPU composite API of mvr.
//
// composeGpu(format, views, options) gives the same image as mvr::composite::compose() with the
// same arguments (compose.h, layout.h, lenticular.h, anaglyph.h are the specification):
//   - the views go up once as one RGBA8 2D-array texture (view i in layer i; reversed for
//     swapEyes, as compose() reverses the order), one full-screen pass of a fragment shader
//     per format family writes an RGBA8 target, which is read back (row 0 = top, as Image);
//     the shader works on the exact 8-bit values (round(texel · 255) in, k / 255 out);
//   - pixel-moving formats (sbs, sbs-half, tb, tb-half, rows, columns, checkerboard,
//     hdmi-frame-packing, quilt) work on the 8-bit integers: copies, and the -half formats'
//     (a + b + 1) / 2 pair average, so they are bit-exact;
//   - lenticular evaluates lenticular.h's formula in double precision (GLSL `precise double`,
//     no fused multiply-add), the same operations in the same order as lenticularView(): on
//     IEEE-double hardware (llvmpipe, every desktop GPU with fp64) it picks the same view for
//     every sub-pixel, i.e. bit-exact;
//   - anaglyph-color is sorbier2008 §4.3's red-cyan anaglyph: additive blending over black,
//     colour mask red + a full-screen pass of the left view, colour mask green/blue + a pass of
//     the right view; it copies channels, so it is bit-exact (the CPU's color matrices copy
//     channels too);
//   - the other anaglyphs run composite::anaglyphGlsl(method) (sRGB decode, 3×3 mixes, encode)
//     in float: within 1/255 per channel of the CPU's table-driven curve
//     (GpuComposeOptions::anaglyphMix replaces that mix, for any anaglyph format);
// Outputs larger than 4096 pixels (or the driver's render-target size) on a side are drawn in
// tiles. The view array texture and the target tile are kept for the next call of the same
// size (freed when a call of another size replaces them).
//
// Errors: exactly the checks of compose() (unknown format, view count, empty or differently
// sized views, and the size rules of composite::outputSize(): odd width / height for the -half
// formats, non-HDMI size, quilt grid, lenticular calibration), as ErrorCode::Usage with the same
// texts, prefixed "mvr::gl::composeGpu(): FMT" where compose() says
// "mvr::composite::compose(): FMT"; a GpuComposeOptions::anaglyphMix that does not compile is
// ErrorCode::Usage with the compile log. "mpo" and "jps" are JPEG files, not
// GPU images: ErrorCode::Unsupported naming composite::compose() / writeComposite(). No GL
// context, a view larger than GL_MAX_TEXTURE_SIZE or more views than
// GL_MAX_ARRAY_TEXTURE_LAYERS: Unsupported. GL requires 4.5 core (+ fp64, core since 4.0).
//
// Threads: any thread may call it; calls are serialised on one process-wide composite context,
// which is current only during the call: the context that was current on the calling thread
// before is current again afterwards.
#pragma once

#include <span>
#include <string>

#include "mvr/composite/compose.h"
#include "mvr/core/image.h"
#include "mvr/core/status.h"

namespace mvr::gl {

/// What only the GPU composite offers; the defaults give composite::compose()'s image.
struct GpuComposeOptions {
    /// Anaglyph formats only (ignored by the others): GLSL (#version 450 core) defining
    /// `vec3 mvrAnaglyph(vec3 left, vec3 right)` to mix the two views with instead of the
    /// format's own (composite::anaglyphGlsl(), or anaglyph-color's colour masks) — e.g. to try
    /// other matrices. It gets the 8-bit values as [0, 1] floats; its result is clamped and
    /// rounded to nearest, alpha 255. Empty: the format's own.
    std::string anaglyphMix;
};

/// The image of `format` for `views` (left to right, one size), composed on the GPU. See above.
Result<Image> composeGpu(const std::string& format, std::span<const Image> views,
                         const composite::ComposeOptions& options = {},
                         const GpuComposeOptions& gpu = {});

/// True for the formats composeGpu() composes: the rows of composite::formats() with a GPU plan
/// (FormatInfo::gpu != GpuPlan::None) — every built-in image format; not the JPEG files (jps,
/// mpo) nor a registered format, which `--backend gl` composes on the CPU (composeFor()).
bool composeGpuSupports(const std::string& format);

}  // namespace mvr::gl

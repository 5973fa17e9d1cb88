// mvr/core/antialias.h — spatial anti-aliasing (issue 38, `--aa N`): N samples a pixel at the
// standard multisample positions, rendered as N sub-pixel-offset passes of the whole rig and
// resolved (box filter: the mean colour, the nearest depth).
//
// Two ways, the same positions and the same resolve:
// - Sub-pixel passes (soft, vk, and gl where the driver or the method cannot multisample N):
//   RenderSettings::samples > 1 makes a backend's renderInto() call renderSampled(), which
//   renders the rig N times with every view (and, for the soft backend's shear form, the centre
//   camera: Rig::clipJitter) moved by the sample's offset, one sample a pixel each, and resolves
//   them. So soft:unified equals soft:multipass bit for bit at any N (each pass is an exact
//   pair). One shading per sample (supersampling): the cost is N renders (bench/README.md).
// - Multisampled targets (gl, where the driver takes N samples: src/gl/multisample.cpp): N
//   coverage and depth samples a pixel, one shading a pixel (MSAA), resolved on the device by
//   the formula below; RenderStats::samples says N. Within gl's bound of soft's passes
//   (tests/conformance/tolerances.h): the coverage is the same, the shading is one a pixel
//   and primitive (centroid interpolation: at a covered sample) where the passes average N.
//
// Sample positions: Direct3D's standard multisample patterns (D3D11_STANDARD_MULTISAMPLE_
// PATTERN; the positions GL drivers use on desktop GPUs), in 1/16 pixel from the pixel centre,
// x right, y down (rows top first, as mvr's images):
//     1: (0, 0)
//     2: (4, 4) (−4, −4)
//     4: (−2, −6) (6, −2) (−6, 2) (2, 6)
//     8: (1, −3) (−1, 3) (5, 1) (−3, −5) (−5, 5) (−7, −1) (3, 7) (7, −7)
// The resolve: colour channel = (Σ samples + N/2) / N (integer, round half up), alpha the same;
// depth = the nearest sample (the depth outputs, the comfort report and auto convergence read
// it); a device-measured depth range (RenderOutput::depthRange) the union over the passes'
// samples, or, multisampled, the range of the resolved (nearest-sample) depth.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include <glm/glm.hpp>

#include "mvr/core/render.h"

namespace mvr {

/// Whether `samples` is a sample count --aa takes: 1, 2, 4 or 8.
bool validSampleCount(int samples);

/// The sample positions of `samples` (1, 2, 4, 8), pixels from the pixel centre, x right,
/// y down. Precondition: validSampleCount(samples).
std::span<const glm::vec2> samplePositions(int samples);

/// `rig` with every view's clipFromView moved so that each pixel centre of a width×height
/// view samples the scene at centre + `offsetPx` (x right, y down), and Rig::clipJitter set
/// to the same NDC offset per unit w for the centre camera.
Rig offsetRig(const Rig& rig, glm::vec2 offsetPx, int width, int height);

/// One more pass added into the sums: sums[i] += bytes[i], for `count` bytes (renderSampled()'s,
/// and that of a panel composed per pass).
void accumulateSamples(const std::uint8_t* bytes, std::uint16_t* sums, std::size_t count);

/// The resolve of N passes' sums (N = 2, 4, 8): out[i] = (sums[i] + N/2) / N, for `count`
/// bytes — renderSampled()'s, and that of a panel composed per pass (mvr/session/direct.h).
void resolveSampleSums(const std::uint16_t* sums, std::uint8_t* out, std::size_t count,
                       int samples);

/// Renders `settings.samples` sub-pixel passes of `rig` on `backend` (its renderInto() with
/// samples = 1) and resolves them into `out` (the header). Errors: the backend's, and Usage
/// for a sample count other than 1, 2, 4, 8.
Status renderSampled(Backend& backend, const Scene& scene, const Rig& rig,
                     const RenderSettings& settings, const std::string& method,
                     RenderOutput& out);

}  // namespace mvr

// mvr/composite/jpeg.h — JPEG, JPS and MPO (CIPA DC-007 Multi-Picture Format) encode/decode.
//
// JPEG goes through libjpeg-turbo (Debian libjpeg-dev): it gives quality and chroma-subsampling
// control (mvr writes 4:4:4 so round trips stay close), decodes every JPEG flavour (progressive,
// grayscale, restart markers), and reports corrupt or truncated data — which mvr turns into an
// error instead of libjpeg's gray fill ("never a silently wrong image").
//
// MPO layout written by encodeMpo() (all MPF values big-endian, offsets relative to the MP
// header = the "MM" byte order mark inside the first image's APP2):
//   image 1: SOI, APP1 "Exif" (minimal IFD0), APP2 "MPF" {MP Index IFD: MPFVersion "0100",
//            NumberOfImages N, MPEntry ×N; MP Attribute IFD}, JPEG data, EOI
//   image k: SOI, APP1 "Exif", APP2 "MPF" {MP Attribute IFD}, JPEG data, EOI
//   MP entry: attribute = type 0x020002 "multi-frame disparity" (image 1 also flagged
//             "representative"), size in bytes, offset (0 for image 1), no dependents.
//   MP Attribute IFD of image k: MPFVersion, MPIndividualNum k, BaseViewpointNum,
//             ConvergenceAngle (SRATIONAL, degrees), BaselineLength (RATIONAL, metres),
//             AxisDistanceX (SRATIONAL, metres: signed x offset of view k from the base view).
// Images are in view order (left to right), as the standard expects for disparity images.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "mvr/composite/compose.h"
#include "mvr/core/image.h"
#include "mvr/core/status.h"
#include "mvr/io/jpeg.h"

namespace mvr::composite {

/// Encodes RGB of `image` (alpha dropped) as a baseline JPEG, 4:4:4, `quality` 1..100.
/// Errors: Usage (empty image, quality out of range), Internal (libjpeg failure).
Result<std::vector<std::uint8_t>> encodeJpeg(const Image& image, int quality);

/// The decoder is mvr::io's (mvr/io/jpeg.h), here under its old name too.
using mvr::decodeJpeg;

/// Builds an MPO file of `views` (2..N, one size), in view order; options.swapEyes reverses
/// it. Uses options.jpegQuality, baseline, convergence, baseViewpoint.
Result<std::vector<std::uint8_t>> encodeMpo(std::span<const Image> views,
                                            const ComposeOptions& options);

/// The byte ranges of the images an MPO holds, from its first image's MP Index IFD.
/// A plain JPEG (no MPF) gives one range covering all of it. Errors: Input (bad structure,
/// entries outside the file).
struct MpoImageRange {
    std::size_t offset;
    std::size_t size;
};
Result<std::vector<MpoImageRange>> mpoImageRanges(std::span<const std::uint8_t> data,
                                                  const std::string& what);

/// Decodes all images of an MPO (or the one image of a plain JPEG). Errors: as above.
Result<std::vector<Image>> decodeMpo(std::span<const std::uint8_t> data, const std::string& what);

/// JPS picture: `left` and `right` side by side with the RIGHT view on the left half (the
/// cross-eyed order JPS viewers expect). encodeJps() returns the JPEG bytes.
Result<std::vector<std::uint8_t>> encodeJps(const Image& left, const Image& right, int quality);
/// Encodes an already composed JPS picture (right | left) with the APP3 "_JPSJPS_" descriptor
/// (stereo, side by side, right image first).
Result<std::vector<std::uint8_t>> encodeJpsPicture(const Image& picture, int quality);
/// Splits a decoded JPS picture (even width) into {left, right}. Errors: Input for odd width.
Result<std::vector<Image>> splitJps(const Image& picture, const std::string& what);

/// Whole-file helpers. Errors: Input (read) / Output (write) naming the path. Only a regular
/// file is read ("PATH: not a regular file (a FIFO)"): a FIFO or a device is never opened.
Result<std::vector<std::uint8_t>> readFileBytes(const std::filesystem::path& path);
Status writeFileBytes(const std::filesystem::path& path, std::span<const std::uint8_t> bytes);
Result<Image> readJpeg(const std::filesystem::path& path);
Status writeJpeg(const std::filesystem::path& path, const Image& image, int quality);

}  // namespace mvr::composite

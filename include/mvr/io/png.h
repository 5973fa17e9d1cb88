// mvr/io/png.h — PNG files and bytes through libpng: mvr::Image / mvr::DepthImage (core's
// in-memory types) to and from PNG. Part of mvr::io.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "mvr/core/image.h"
#include "mvr/core/status.h"

namespace mvr {

/// How hard PNG files are compressed (lossless in every mode: the pixels decode identical).
/// Every PNG mvr writes is Fast unless asked (`--png-compression`, Python png_compression=).
/// Measured on a 420x560 view of 9 bunnies (one core): Fast 3.9 ms / 103 kB (zlib level 1,
/// the Sub filter), Default 14 ms / 99 kB (libpng's simplified writer, as before), Small 36 ms /
/// 92 kB (level 9, every filter tried per row).
enum class PngCompression { Fast, Default, Small };
/// "fast" | "default" | "small". Errors: Usage naming the value.
Result<PngCompression> parsePngCompression(std::string_view name);
const char* pngCompressionName(PngCompression c);

/// Writes an RGBA8 PNG through libpng. Errors: ErrorCode::Output naming the path.
Status writePng(const std::filesystem::path& path, const Image& image,
                PngCompression compression = PngCompression::Fast);

/// The bytes of writePng()'s file, in memory (the same bytes). Errors: ErrorCode::Output.
Result<std::vector<std::uint8_t>> encodePng(const Image& image,
                                            PngCompression compression = PngCompression::Fast);
/// Writes `bytes` (an encoded file) to `path`. Errors: ErrorCode::Output naming the path with
/// the system's reason (mvr/core/output_file.h).
Status writeBytes(const std::filesystem::path& path, std::span<const std::uint8_t> bytes);

/// Reads a PNG file (any bit depth / color type, converted to RGBA8) through libpng.
/// Errors: ErrorCode::Input naming the path and the problem (missing, not a regular file — a
/// directory, FIFO or device is never opened —, not a PNG, truncated).
Result<Image> readPng(const std::filesystem::path& path);

/// Decodes PNG bytes in memory (any bit depth / color type, converted to RGBA8) through
/// libpng, as readPng(). Errors: ErrorCode::Input, "WHAT: not a readable PNG (...)" / ...
Result<Image> decodePng(std::span<const std::uint8_t> data, const std::string& what);

/// Writes a depth image as a 16-bit grayscale PNG (0 = near, 65535 = far / empty), for looking at.
Status writeDepthPng(const std::filesystem::path& path, const DepthImage& depth,
                     PngCompression compression = PngCompression::Fast);

}  // namespace mvr

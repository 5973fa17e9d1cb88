// png.cpp — the PNG codec through libpng (png.h).
#include "mvr/io/png.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <vector>

#include <fmt/core.h>
#include <png.h>

#include "mvr/core/input_file.h"
#include "mvr/core/output_file.h"

namespace mvr {

namespace {

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};

// libpng reports errors by longjmp; the simplified png_image API wraps that for us and
// returns failure with a message in image.message, which keeps this code exception-free.
// The full libpng API for a chosen zlib level and filter set (the simplified API has neither).
// libpng reports errors by longjmp: nothing with a destructor lives in this function.
struct PngError {
    char message[256] = "";
};
void onPngError(png_structp png, png_const_charp message) {
    auto* e = static_cast<PngError*>(png_get_error_ptr(png));
    std::snprintf(e->message, sizeof e->message, "%s", message);
    png_longjmp(png, 1);
}
void onPngWarning(png_structp, png_const_charp) {}

void appendBytes(png_structp png, png_bytep data, png_size_t length) {
    auto* out = static_cast<std::vector<std::uint8_t>*>(png_get_io_ptr(png));
    out->insert(out->end(), data, data + length);
}
void flushNothing(png_structp) {}

bool encodePngTuned(std::vector<std::uint8_t>& out, int width, int height, bool gray16,
                    const void* pixels, std::ptrdiff_t rowBytes, int level, int filters,
                    PngError& error) {
    png_structp png =
        png_create_write_struct(PNG_LIBPNG_VER_STRING, &error, onPngError, onPngWarning);
    if (!png) return false;
    png_infop info = png_create_info_struct(png);
    if (!info || setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return false;
    }
    png_set_write_fn(png, &out, appendBytes, flushNothing);
    png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), gray16 ? 16 : 8,
                 gray16 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGBA, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(png, level);
    png_set_filter(png, PNG_FILTER_TYPE_BASE, filters);
    png_write_info(png, info);
    if (gray16) {
        const std::uint16_t probe = 1;
        if (*reinterpret_cast<const std::uint8_t*>(&probe) == 1) png_set_swap(png);  // LE host
    }
    const auto* row = static_cast<const std::uint8_t*>(pixels);
    for (int y = 0; y < height; ++y) png_write_row(png, row + std::ptrdiff_t(y) * rowBytes);
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    return true;
}

/// The PNG file's bytes, in memory. Errors: "WHO: <libpng's reason>" (ErrorCode::Output).
Result<std::vector<std::uint8_t>> encodePngRaw(std::string_view who, int width, int height,
                                               png_uint_32 format, const void* pixels,
                                               std::ptrdiff_t rowStride,
                                               PngCompression compression) {
    std::vector<std::uint8_t> bytes;
    if (compression != PngCompression::Default) {
        const bool gray16 = format == PNG_FORMAT_LINEAR_Y;
        const std::ptrdiff_t rowBytes = rowStride * (gray16 ? 2 : 1);  // stride is in components
        PngError error;
        const bool fast = compression == PngCompression::Fast;
        // About what fast deflate makes of a rendered view: fewer reallocations.
        bytes.reserve(std::size_t(width) * std::size_t(height) * (gray16 ? 2 : 4) / 4 + 1024);
        if (!encodePngTuned(bytes, width, height, gray16, pixels, rowBytes, fast ? 1 : 9,
                            fast ? PNG_FILTER_SUB : PNG_ALL_FILTERS, error)) {
            return outputError(
                fmt::format("{}: {}", who, *error.message ? error.message : "libpng failed"));
        }
        return bytes;
    }
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    image.width = static_cast<png_uint_32>(width);
    image.height = static_cast<png_uint_32>(height);
    image.format = format;
    png_alloc_size_t size = 0;
    // Its size first, then the bytes (libpng's simplified writer, as png_image_write_to_stdio).
    if (png_image_write_to_memory(&image, nullptr, &size, 0, pixels,
                                  static_cast<png_int_32>(rowStride), nullptr)) {
        bytes.resize(size);
        if (png_image_write_to_memory(&image, bytes.data(), &size, 0, pixels,
                                      static_cast<png_int_32>(rowStride), nullptr)) {
            bytes.resize(size);
            return bytes;
        }
    }
    const std::string why = image.message;
    png_image_free(&image);
    return outputError(fmt::format("{}: {}", who, why));
}

Status writePngRaw(const std::filesystem::path& path, int width, int height, png_uint_32 format,
                   const void* pixels, std::ptrdiff_t rowStride, PngCompression compression) {
    auto bytes = encodePngRaw(path.string(), width, height, format, pixels, rowStride, compression);
    if (!bytes) {
        errno = 0;
        const std::string& m = bytes.status().message();
        return writeError(path, m.substr(std::min(m.size(), path.string().size() + 2)));
    }
    return writeBytes(path, *bytes);
}

}  // namespace

Result<PngCompression> parsePngCompression(std::string_view name) {
    if (name == "fast") return PngCompression::Fast;
    if (name == "default") return PngCompression::Default;
    if (name == "small") return PngCompression::Small;
    return usageError(fmt::format("--png-compression {}: expected fast, default or small", name));
}

const char* pngCompressionName(PngCompression c) {
    switch (c) {
        case PngCompression::Fast: return "fast";
        case PngCompression::Small: return "small";
        default: return "default";
    }
}

Status writePng(const std::filesystem::path& path, const Image& image,
                PngCompression compression) {
    if (image.empty() || image.rgba.size() != std::size_t(image.width) * image.height * 4) {
        return outputError(
            fmt::format("mvr::writePng(): {}: image is empty or its size ({}x{}) "
                        "does not match its data",
                        path.string(), image.width, image.height));
    }
    return writePngRaw(path, image.width, image.height, PNG_FORMAT_RGBA, image.rgba.data(),
                       image.width * 4, compression);
}

Status writeDepthPng(const std::filesystem::path& path, const DepthImage& depth,
                     PngCompression compression) {
    if (depth.width <= 0 || depth.height <= 0) {
        return outputError(
            fmt::format("mvr::writeDepthPng(): {}: empty depth image", path.string()));
    }
    std::vector<std::uint16_t> gray(depth.depth.size());
    for (std::size_t i = 0; i < gray.size(); ++i) {
        const float d =
            std::isfinite(depth.depth[i]) ? std::clamp(depth.depth[i], 0.0f, 1.0f) : 1.0f;
        gray[i] = static_cast<std::uint16_t>(d * 65535.0f + 0.5f);
    }
    // PNG_FORMAT_LINEAR_Y: 16-bit gray samples in native byte order; libpng swaps them.
    return writePngRaw(path, depth.width, depth.height, PNG_FORMAT_LINEAR_Y, gray.data(),
                       depth.width, compression);
}

Status writeBytes(const std::filesystem::path& path, std::span<const std::uint8_t> bytes) {
    errno = 0;
    std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "wb"));
    if (!file) return writeError(path, "cannot open for writing");
    const bool written = std::fwrite(bytes.data(), 1, bytes.size(), file.get()) == bytes.size();
    // A full disk may only show when the last buffer is written out, at the close.
    if (!written || std::fflush(file.get()) != 0 || std::ferror(file.get()) ||
        std::fclose(file.release()) != 0) {
        return writeError(path, "write failed");
    }
    return {};
}

Result<std::vector<std::uint8_t>> encodePng(const Image& image, PngCompression compression) {
    if (image.empty() || image.rgba.size() != std::size_t(image.width) * image.height * 4) {
        return outputError(fmt::format("mvr::encodePng(): image is empty or its size ({}x{}) "
                                       "does not match its data",
                                       image.width, image.height));
    }
    return encodePngRaw("mvr::encodePng()", image.width, image.height, PNG_FORMAT_RGBA,
                        image.rgba.data(), image.width * 4, compression);
}

Result<Image> readPng(const std::filesystem::path& path) {
    // A regular file only: a FIFO or a device (/dev/zero) would block or never end.
    if (Status s = checkRegularFile(path, fmt::format("mvr::readPng(): {}", path.string())); !s)
        return s;
    std::error_code ec;
    std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
    if (!file) {
        return inputError(
            fmt::format("mvr::readPng(): {}: cannot open for reading", path.string()));
    }
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_stdio(&image, file.get())) {
        const std::string why = image.message;
        png_image_free(&image);
        return inputError(
            fmt::format("mvr::readPng(): {}: not a readable PNG ({})", path.string(), why));
    }
    if (image.width == 0 || image.height == 0 || image.width > 65536 || image.height > 65536) {
        png_image_free(&image);
        return inputError(fmt::format("mvr::readPng(): {}: unsupported size {}x{}", path.string(),
                                      image.width, image.height));
    }
    // A header that claims more than the file can hold is refused before allocating: deflate
    // expands at most ~1032:1 and a PNG row holds at least a filter byte and 1 bit per pixel.
    const double fileBytes = double(std::filesystem::file_size(path, ec));
    const double rawBytes = double(image.height) * (1.0 + std::ceil(double(image.width) / 8.0));
    if (!ec && rawBytes > fileBytes * 1032.0 + 65536.0) {
        png_image_free(&image);
        return inputError(fmt::format(
            "mvr::readPng(): {}: header claims {}x{} pixels but the file's {:.0f} bytes cannot "
            "hold them (truncated or corrupt?)",
            path.string(), image.width, image.height, fileBytes));
    }
    image.format = PNG_FORMAT_RGBA;
    Image out(static_cast<int>(image.width), static_cast<int>(image.height));
    if (!png_image_finish_read(&image, nullptr, out.rgba.data(), 0, nullptr)) {
        const std::string why = image.message;
        png_image_free(&image);
        return inputError(
            fmt::format("mvr::readPng(): {}: corrupt or truncated PNG ({})", path.string(), why));
    }
    return out;
}

Result<Image> decodePng(std::span<const std::uint8_t> data, const std::string& what) {
    if (data.empty()) return inputError(fmt::format("{}: empty (expected a PNG)", what));
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_memory(&image, data.data(), data.size())) {
        const std::string why = image.message;
        png_image_free(&image);
        return inputError(fmt::format("{}: not a readable PNG ({})", what, why));
    }
    if (image.width == 0 || image.height == 0 || image.width > 65536 || image.height > 65536) {
        png_image_free(&image);
        return inputError(
            fmt::format("{}: unsupported PNG size {}x{}", what, image.width, image.height));
    }
    // As readPng(): a header that claims more than the bytes can hold is refused first.
    const double rawBytes = double(image.height) * (1.0 + std::ceil(double(image.width) / 8.0));
    if (rawBytes > double(data.size()) * 1032.0 + 65536.0) {
        png_image_free(&image);
        return inputError(fmt::format(
            "{}: PNG header claims {}x{} pixels but its {} bytes cannot hold them (truncated or "
            "corrupt?)",
            what, image.width, image.height, data.size()));
    }
    image.format = PNG_FORMAT_RGBA;
    Image out(static_cast<int>(image.width), static_cast<int>(image.height));
    if (!png_image_finish_read(&image, nullptr, out.rgba.data(), 0, nullptr)) {
        const std::string why = image.message;
        png_image_free(&image);
        return inputError(fmt::format("{}: corrupt or truncated PNG ({})", what, why));
    }
    return out;
}

}  // namespace mvr

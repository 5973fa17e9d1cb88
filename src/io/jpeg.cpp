// jpeg.cpp — the JPEG decoder through libjpeg-turbo (jpeg.h). The encoder and the JPS / MPO
// files are mvr::composite's (src/composite/jpeg.cpp); both handle libjpeg's errors through
// jpeg_errors.h.
#include "mvr/io/jpeg.h"

#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include <fmt/core.h>
#include <jpeglib.h>

#include "jpeg_errors.h"

namespace mvr {
namespace {

using ::mvr::detail::JpegErrors;
using ::mvr::detail::installJpegErrors;

struct DecodeState {
    jpeg_decompress_struct cinfo{};
    JpegErrors err;
    bool created = false;
    Image image;
    ~DecodeState() {
        if (created) jpeg_destroy_decompress(&cinfo);
    }
};

constexpr long long kMaxPixels = 1LL << 28;  // 16384 × 16384

bool isJpeg(std::span<const std::uint8_t> d) {
    return d.size() >= 3 && d[0] == 0xFF && d[1] == 0xD8 && d[2] == 0xFF;
}

}  // namespace

Result<Image> decodeJpeg(std::span<const std::uint8_t> data, const std::string& what) {
    if (data.empty()) return inputError(fmt::format("{}: empty file (expected a JPEG)", what));
    if (!isJpeg(data))
        return inputError(fmt::format("{}: not a JPEG file (no SOI marker FF D8 FF)", what));
    auto st = std::make_unique<DecodeState>();
    installJpegErrors(st->err);
    st->cinfo.err = &st->err.pub;
    if (setjmp(st->err.jump)) {
        return inputError(fmt::format("{}: corrupt JPEG: {}", what, st->err.message));
    }
    jpeg_create_decompress(&st->cinfo);
    st->created = true;
    jpeg_mem_src(&st->cinfo, data.data(), static_cast<unsigned long>(data.size()));
    jpeg_read_header(&st->cinfo, TRUE);
    if (st->cinfo.jpeg_color_space == JCS_CMYK || st->cinfo.jpeg_color_space == JCS_YCCK)
        return unsupportedError(
            fmt::format("{}: CMYK JPEG (expected RGB/YCbCr or grayscale)", what));
    const long long pixels = static_cast<long long>(st->cinfo.image_width) *
                             static_cast<long long>(st->cinfo.image_height);
    if (pixels <= 0 || pixels > kMaxPixels)
        return inputError(fmt::format("{}: JPEG of {}x{} pixels (expected 1..{} pixels)", what,
                                      st->cinfo.image_width, st->cinfo.image_height, kMaxPixels));
    // A header that claims more pixels than the data can code is refused before allocating:
    // with Huffman coding every 8x8 block of a scan takes at least one bit, so a file holds at
    // most ~512 pixels per byte (1024 allowed). Arithmetic coding has no such floor.
    if (!st->cinfo.arith_code &&
        static_cast<double>(pixels) > static_cast<double>(data.size()) * 1024.0 + 1048576.0) {
        return inputError(fmt::format(
            "{}: JPEG header claims {}x{} pixels but the file's {} bytes cannot hold them "
            "(truncated or corrupt?)",
            what, st->cinfo.image_width, st->cinfo.image_height, data.size()));
    }
    st->cinfo.out_color_space = JCS_EXT_RGBA;
    jpeg_start_decompress(&st->cinfo);
    st->image =
        Image(static_cast<int>(st->cinfo.output_width), static_cast<int>(st->cinfo.output_height));
    while (st->cinfo.output_scanline < st->cinfo.output_height) {
        JSAMPROW row = st->image.row(static_cast<int>(st->cinfo.output_scanline));
        if (jpeg_read_scanlines(&st->cinfo, &row, 1) != 1) break;
        // Stop at the first corrupt-data warning: libjpeg would fill every remaining row of
        // a header's claimed size (found by fuzzing: a 314-byte file claiming 1552x57857).
        if (st->err.warnings > 0) break;
    }
    if (st->err.warnings == 0) jpeg_finish_decompress(&st->cinfo);
    if (st->err.warnings > 0)
        return inputError(
            fmt::format("{}: corrupt or truncated JPEG data: {}", what, st->err.warning));
    return std::move(st->image);
}

}  // namespace mvr

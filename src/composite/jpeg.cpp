#include "mvr/composite/jpeg.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>

#include <fmt/core.h>
#include <jpeglib.h>

#include "jpeg_errors.h"  // src/io: libjpeg error handling, shared with the decoder
#include "mvr/core/output_file.h"
#include "mvr/composite/layout.h"
#include "mvr/core/input_file.h"

namespace mvr::composite {
namespace {

using ::mvr::detail::JpegErrors;
using ::mvr::detail::installJpegErrors;

struct EncodeState {
    jpeg_compress_struct cinfo{};
    JpegErrors err;
    bool created = false;
    unsigned char* buffer = nullptr;
    unsigned long size = 0;
    ~EncodeState() {
        if (created) jpeg_destroy_compress(&cinfo);
        std::free(buffer);
    }
};

// `app3`: payload of an APP3 segment written right after the JFIF header (JPS descriptor).
Result<std::vector<std::uint8_t>> encodeJpegImpl(const Image& image, int quality, bool jfif,
                                                 std::span<const std::uint8_t> app3 = {}) {
    const char* who = "mvr::composite::encodeJpeg()";
    if (image.empty() ||
        image.rgba.size() != static_cast<std::size_t>(image.width) * image.height * 4)
        return usageError(
            fmt::format("{}: empty or inconsistent image {}x{}", who, image.width, image.height));
    if (quality < 1 || quality > 100)
        return usageError(fmt::format("{}: quality {} (expected 1..100)", who, quality));
    if (image.width > 65500 || image.height > 65500)
        return usageError(fmt::format("{}: image {}x{} exceeds JPEG's 65500 pixels per side", who,
                                      image.width, image.height));
    auto st = std::make_unique<EncodeState>();
    installJpegErrors(st->err);
    st->cinfo.err = &st->err.pub;
    if (setjmp(st->err.jump)) {
        return internalError(fmt::format("{}: libjpeg: {}", who, st->err.message));
    }
    jpeg_create_compress(&st->cinfo);
    st->created = true;
    jpeg_mem_dest(&st->cinfo, &st->buffer, &st->size);
    st->cinfo.image_width = static_cast<JDIMENSION>(image.width);
    st->cinfo.image_height = static_cast<JDIMENSION>(image.height);
    st->cinfo.input_components = 4;
    st->cinfo.in_color_space = JCS_EXT_RGBA;
    jpeg_set_defaults(&st->cinfo);
    jpeg_set_quality(&st->cinfo, quality, TRUE);
    for (int c = 0; c < st->cinfo.num_components; ++c) {
        st->cinfo.comp_info[c].h_samp_factor = 1;  // 4:4:4: no chroma subsampling
        st->cinfo.comp_info[c].v_samp_factor = 1;
    }
    st->cinfo.optimize_coding = TRUE;
    st->cinfo.write_JFIF_header = jfif ? TRUE : FALSE;
    jpeg_start_compress(&st->cinfo, TRUE);
    if (!app3.empty())
        jpeg_write_marker(&st->cinfo, JPEG_APP0 + 3, app3.data(),
                          static_cast<unsigned>(app3.size()));
    while (st->cinfo.next_scanline < st->cinfo.image_height) {
        JSAMPROW row = const_cast<JSAMPROW>(image.row(static_cast<int>(st->cinfo.next_scanline)));
        jpeg_write_scanlines(&st->cinfo, &row, 1);
    }
    jpeg_finish_compress(&st->cinfo);
    return std::vector<std::uint8_t>(st->buffer, st->buffer + st->size);
}

// ---- big-endian TIFF-style writer for the MPF segments -----------------------------------------
struct Writer {
    std::vector<std::uint8_t> bytes;
    void u8(std::uint8_t v) { bytes.push_back(v); }
    void u16(std::uint32_t v) {
        u8(static_cast<std::uint8_t>(v >> 8));
        u8(static_cast<std::uint8_t>(v));
    }
    void u32(std::uint32_t v) {
        u16(v >> 16);
        u16(v & 0xffff);
    }
    void raw(const char* s, std::size_t n) { bytes.insert(bytes.end(), s, s + n); }
    // One 12-byte IFD entry whose value fits in 4 bytes (or is an offset).
    void entry(std::uint16_t tag, std::uint16_t type, std::uint32_t count, std::uint32_t value) {
        u16(tag);
        u16(type);
        u32(count);
        u32(value);
    }
};

enum : std::uint16_t {
    kByte = 1,
    kShort = 3,
    kLong = 4,
    kRational = 5,
    kUndefined = 7,
    kSRational = 10
};
constexpr std::uint32_t kMpfVersion = 0x30313030;  // "0100"
constexpr std::uint32_t kTypeDisparity = 0x020002;
constexpr std::uint32_t kFlagRepresentative = 0x20000000;
constexpr std::uint32_t kRationalScale = 1000000;  // metres with µm resolution, degrees / 1e6

std::uint32_t toRational(double v) {
    const double scaled = std::round(std::clamp(v, 0.0, 4294.0) * kRationalScale);
    return static_cast<std::uint32_t>(scaled);
}
std::uint32_t toSRational(double v) {
    const double scaled = std::round(std::clamp(v, -2147.0, 2147.0) * kRationalScale);
    return static_cast<std::uint32_t>(static_cast<std::int32_t>(scaled));
}

// APP1 "Exif" with a minimal IFD0 (Orientation = 1): MPF files are Exif-based (DC-007 §5.1).
std::vector<std::uint8_t> exifSegment() {
    Writer w;
    w.u16(0xFFE1);
    w.u16(2 + 6 + 8 + 2 + 12 + 4);
    w.raw("Exif\0\0", 6);
    w.raw("MM\0\x2A", 4);
    w.u32(8);
    w.u16(1);
    w.entry(0x0112, kShort, 1, 1u << 16);  // Orientation: top-left (SHORT left-aligned)
    w.u32(0);
    return w.bytes;
}

constexpr std::uint32_t kAttributeEntries = 6;
constexpr std::uint32_t kAttributeIfdSize = 2 + kAttributeEntries * 12 + 4 + 3 * 8;

// Appends the MP Attribute IFD at MP-header offset `at` (= w.bytes.size() - headerStart).
void writeAttributeIfd(Writer& w, std::uint32_t at, std::uint32_t individualNum,
                       std::uint32_t baseViewpoint, double convergenceDeg, double baselineM,
                       double axisDistanceXM) {
    const std::uint32_t values = at + 2 + kAttributeEntries * 12 + 4;
    w.u16(kAttributeEntries);
    w.entry(0xB000, kUndefined, 4, kMpfVersion);
    w.entry(0xB101, kLong, 1, individualNum);
    w.entry(0xB204, kLong, 1, baseViewpoint);
    w.entry(0xB205, kSRational, 1, values);
    w.entry(0xB206, kRational, 1, values + 8);
    w.entry(0xB208, kSRational, 1, values + 16);
    w.u32(0);  // no next IFD
    w.u32(toSRational(convergenceDeg));
    w.u32(kRationalScale);
    w.u32(toRational(baselineM));
    w.u32(kRationalScale);
    w.u32(toSRational(axisDistanceXM));
    w.u32(kRationalScale);
}

// ---- reading ---------------------------------------------------------------------------------
struct Reader {
    std::span<const std::uint8_t> data;
    bool bigEndian = true;
    bool has(std::size_t at, std::size_t n) const {
        return at <= data.size() && n <= data.size() - at;
    }
    std::uint32_t u16(std::size_t at) const {
        return bigEndian ? (data[at] << 8 | data[at + 1]) : (data[at + 1] << 8 | data[at]);
    }
    std::uint32_t u32(std::size_t at) const {
        return bigEndian ? (u16(at) << 16 | u16(at + 2)) : (u16(at + 2) << 16 | u16(at));
    }
};

bool isJpeg(std::span<const std::uint8_t> d) {
    return d.size() >= 3 && d[0] == 0xFF && d[1] == 0xD8 && d[2] == 0xFF;
}

// Finds the APP2 "MPF" payload (the MP header offset in the file), or npos when there is none
// before the first SOS. Errors for a marker structure that runs off the data.
Result<std::size_t> findMpfHeader(std::span<const std::uint8_t> d, const std::string& what) {
    const auto bad = [&](const char* why) {
        return Status(inputError(fmt::format("{}: malformed JPEG: {}", what, why)));
    };
    if (!isJpeg(d)) return bad("no SOI marker at the start (not a JPEG file)");
    std::size_t at = 2;
    while (true) {
        if (at + 4 > d.size()) return bad("file ends inside the JPEG header (truncated)");
        if (d[at] != 0xFF) return bad("expected a marker in the JPEG header");
        const std::uint8_t marker = d[at + 1];
        if (marker == 0xFF) {  // fill byte
            ++at;
            continue;
        }
        if (marker == 0xDA || marker == 0xD9) return std::size_t(std::string::npos);
        const std::size_t len = static_cast<std::size_t>(d[at + 2]) << 8 | d[at + 3];
        if (len < 2 || at + 2 + len > d.size())
            return bad("a header segment runs past the end of the file (truncated)");
        if (marker == 0xE2 && len >= 2 + 4 + 8 && std::memcmp(&d[at + 4], "MPF\0", 4) == 0)
            return at + 8;
        at += 2 + len;
    }
}

}  // namespace

// ---- public: JPEG
// ---------------------------------------------------------------------------------
Result<std::vector<std::uint8_t>> encodeJpeg(const Image& image, int quality) {
    return encodeJpegImpl(image, quality, true);
}


// ---- public: MPO -------------------------------------------------------------------------------
Result<std::vector<std::uint8_t>> encodeMpo(std::span<const Image> views,
                                            const ComposeOptions& options) {
    const char* who = "mvr::composite::encodeMpo()";
    if (Status s = validateViews(views, 2, 4096, who); !s) return s;
    const int n = static_cast<int>(views.size());
    if (!std::isfinite(options.baseline) || options.baseline < 0 ||
        !std::isfinite(options.convergence) || options.convergence < 0)
        return usageError(fmt::format("{}: baseline {} / convergence {} (expected finite, >= 0)",
                                      who, options.baseline, options.convergence));
    const int base = options.baseViewpoint > 0 ? options.baseViewpoint : (n + 1) / 2;
    if (base > n)
        return usageError(
            fmt::format("{}: base viewpoint {} of {} views (expected 1..{})", who, base, n, n));
    const double angle = convergenceAngleDegrees(options.baseline, options.convergence);

    std::vector<std::vector<std::uint8_t>> jpegs;
    for (int k = 0; k < n; ++k) {
        const Image& view = views[options.swapEyes ? n - 1 - k : k];
        Result<std::vector<std::uint8_t>> j = encodeJpegImpl(view, options.jpegQuality, false);
        if (!j) return j.status();
        jpegs.push_back(std::move(*j));
    }
    const std::vector<std::uint8_t> exif = exifSegment();
    // APP2 segment sizes: marker (2) + length (2) + "MPF\0" (4) + MP header (8) + IFDs.
    const std::uint32_t indexIfdSize = 2 + 3 * 12 + 4 + 16u * n;
    const std::uint32_t app2First = 2 + 2 + 4 + 8 + indexIfdSize + kAttributeIfdSize;
    const std::uint32_t app2Other = 2 + 2 + 4 + 8 + kAttributeIfdSize;
    if (app2First - 2 > 0xFFFF) return usageError(fmt::format("{}: too many views ({})", who, n));
    std::vector<std::uint32_t> sizes(n), starts(n);
    std::uint64_t total = 0;
    for (int k = 0; k < n; ++k) {
        sizes[k] = static_cast<std::uint32_t>(jpegs[k].size() + exif.size() +
                                              (k == 0 ? app2First : app2Other));
        starts[k] = static_cast<std::uint32_t>(total);
        total += sizes[k];
    }
    if (total > 0xFFFFFFFFull) return usageError(fmt::format("{}: MPO would exceed 4 GiB", who));
    const std::uint32_t mpHeader = 2 + static_cast<std::uint32_t>(exif.size()) + 4 + 4;

    std::vector<std::uint8_t> file;
    file.reserve(total);
    for (int k = 0; k < n; ++k) {
        Writer w;
        w.u16(0xFFE2);
        w.u16((k == 0 ? app2First : app2Other) - 2);
        w.raw("MPF\0", 4);
        const std::size_t header = w.bytes.size();
        w.raw("MM\0\x2A", 4);
        w.u32(8);
        const double axisX = (k + 1 - base) * options.baseline;
        if (k == 0) {
            // MP Index IFD: version, number of images, MP entries; then the attribute IFD.
            const std::uint32_t entries = 8 + 2 + 3 * 12 + 4;
            w.u16(3);
            w.entry(0xB000, kUndefined, 4, kMpfVersion);
            w.entry(0xB001, kLong, 1, static_cast<std::uint32_t>(n));
            w.entry(0xB002, kUndefined, 16u * n, entries);
            w.u32(8 + indexIfdSize);  // next IFD: the MP Attribute IFD
            for (int e = 0; e < n; ++e) {
                w.u32((e == 0 ? kFlagRepresentative : 0u) | kTypeDisparity);  // format 0 = JPEG
                w.u32(sizes[e]);
                w.u32(e == 0 ? 0u : starts[e] - mpHeader);
                w.u16(0);
                w.u16(0);
            }
        }
        writeAttributeIfd(w, static_cast<std::uint32_t>(w.bytes.size() - header),
                          static_cast<std::uint32_t>(k + 1), static_cast<std::uint32_t>(base),
                          angle, options.baseline, axisX);
        MVR_ASSERT(w.bytes.size() == (k == 0 ? app2First : app2Other));
        file.insert(file.end(), jpegs[k].begin(), jpegs[k].begin() + 2);  // SOI
        file.insert(file.end(), exif.begin(), exif.end());
        file.insert(file.end(), w.bytes.begin(), w.bytes.end());
        file.insert(file.end(), jpegs[k].begin() + 2, jpegs[k].end());
    }
    MVR_ASSERT(file.size() == total);
    return file;
}

Result<std::vector<MpoImageRange>> mpoImageRanges(std::span<const std::uint8_t> data,
                                                  const std::string& what) {
    Result<std::size_t> found = findMpfHeader(data, what);
    if (!found) return found.status();
    if (*found == std::string::npos) return std::vector<MpoImageRange>{{0, data.size()}};
    const std::size_t h = *found;
    const auto bad = [&](const std::string& why) {
        return Status(inputError(fmt::format("{}: malformed MPO index: {}", what, why)));
    };
    Reader r{data};
    if (!r.has(h, 8)) return bad("MP header truncated");
    if (data[h] == 'M' && data[h + 1] == 'M')
        r.bigEndian = true;
    else if (data[h] == 'I' && data[h + 1] == 'I')
        r.bigEndian = false;
    else
        return bad("unknown byte order");
    const std::size_t ifd = h + r.u32(h + 4);
    if (!r.has(ifd, 2)) return bad("MP Index IFD outside the file");
    const std::uint32_t count = r.u16(ifd);
    if (!r.has(ifd + 2, std::size_t(count) * 12)) return bad("MP Index IFD truncated");
    std::uint32_t numberOfImages = 0, entryCount = 0, entryOffset = 0;
    for (std::uint32_t i = 0; i < count; ++i) {
        const std::size_t e = ifd + 2 + i * 12;
        const std::uint32_t tag = r.u16(e);
        if (tag == 0xB001) numberOfImages = r.u32(e + 8);
        if (tag == 0xB002) {
            entryCount = r.u32(e + 4);
            entryOffset = r.u32(e + 8);
        }
    }
    if (numberOfImages == 0 || entryCount != 16 * numberOfImages)
        return bad(fmt::format("NumberOfImages {} does not match {} bytes of MP entries",
                               numberOfImages, entryCount));
    if (numberOfImages > 4096)
        return bad(fmt::format("{} images (expected at most 4096)", numberOfImages));
    if (!r.has(h + entryOffset, entryCount)) return bad("MP entries outside the file");
    std::vector<MpoImageRange> ranges;
    for (std::uint32_t i = 0; i < numberOfImages; ++i) {
        const std::size_t e = h + entryOffset + i * 16;
        const std::uint32_t attribute = r.u32(e);
        const std::uint32_t size = r.u32(e + 4);
        const std::uint32_t offset = r.u32(e + 8);
        const std::size_t start = i == 0 ? 0 : h + offset;
        if ((attribute & 0x07000000) != 0) continue;           // not JPEG data
        if ((attribute & 0x00FF0000) == 0x00010000) continue;  // large thumbnail (preview)
        if (size == 0 || !r.has(start, size))
            return bad(fmt::format("image {} ({} bytes at {}) lies outside the file of {} bytes",
                                   i + 1, size, start, data.size()));
        ranges.push_back({start, size});
    }
    if (ranges.empty()) return bad("no JPEG images listed");
    return ranges;
}

Result<std::vector<Image>> decodeMpo(std::span<const std::uint8_t> data, const std::string& what) {
    Result<std::vector<MpoImageRange>> ranges = mpoImageRanges(data, what);
    if (!ranges) return ranges.status();
    std::vector<Image> images;
    for (std::size_t i = 0; i < ranges->size(); ++i) {
        const MpoImageRange& range = (*ranges)[i];
        const std::string name =
            ranges->size() == 1 ? what : fmt::format("{} (image {})", what, i + 1);
        Result<Image> image = decodeJpeg(data.subspan(range.offset, range.size), name);
        if (!image) return image.status();
        images.push_back(std::move(*image));
    }
    return images;
}

// ---- public: JPS -------------------------------------------------------------------------------
Result<std::vector<std::uint8_t>> encodeJpsPicture(const Image& picture, int quality) {
    // APP3 "_JPSJPS_" stereoscopic descriptor (VRex JPS, as described by P. Bourke, "Stereo
    // image file formats"): descriptor length 4, then separation 0, flags 0 (full size; "left
    // field first" clear = right image on the left), layout 2 = side by side, type 1 = stereo;
    // no comment.
    static constexpr std::uint8_t kJpsDescriptor[] = {'_', 'J', 'P', 'S', 'J', 'P', 'S', '_',
                                                      0,   4,   0,   0,   2,   1,   0,   0};
    return encodeJpegImpl(picture, quality, true, kJpsDescriptor);
}

Result<std::vector<std::uint8_t>> encodeJps(const Image& left, const Image& right, int quality) {
    Result<Image> picture = sideBySide(right, left, false);
    if (!picture) return picture.status();
    return encodeJpsPicture(*picture, quality);
}

Result<std::vector<Image>> splitJps(const Image& picture, const std::string& what) {
    if (picture.empty() || picture.width % 2 != 0)
        return inputError(
            fmt::format("{}: JPS picture {}x{} (expected an even width: right and "
                        "left views side by side)",
                        what, picture.width, picture.height));
    const int w = picture.width / 2;
    Image left(w, picture.height), right(w, picture.height);
    for (int y = 0; y < picture.height; ++y) {
        std::memcpy(right.row(y), picture.row(y), static_cast<std::size_t>(w) * 4);
        std::memcpy(left.row(y), picture.row(y) + static_cast<std::size_t>(w) * 4,
                    static_cast<std::size_t>(w) * 4);
    }
    std::vector<Image> views;
    views.push_back(std::move(left));
    views.push_back(std::move(right));
    return views;
}

// ---- public: files -----------------------------------------------------------------------------
Result<std::vector<std::uint8_t>> readFileBytes(const std::filesystem::path& path) {
    // A regular file only: a FIFO or a device (/dev/zero, /dev/urandom) would block or never end.
    if (Status s = checkRegularFile(path, path.string()); !s) return s;
    std::ifstream in(path, std::ios::binary);
    if (!in) return inputError(fmt::format("{}: cannot open for reading", path.string()));
    std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                    std::istreambuf_iterator<char>());
    if (in.bad()) return inputError(fmt::format("{}: read error", path.string()));
    return bytes;
}

Status writeFileBytes(const std::filesystem::path& path, std::span<const std::uint8_t> bytes) {
    errno = 0;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) return writeError(path, "cannot open for writing");
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) return writeError(path, "write failed");
    return Status::ok();
}

Result<Image> readJpeg(const std::filesystem::path& path) {
    Result<std::vector<std::uint8_t>> bytes = readFileBytes(path);
    if (!bytes) return bytes.status();
    return decodeJpeg(*bytes, path.string());
}

Status writeJpeg(const std::filesystem::path& path, const Image& image, int quality) {
    Result<std::vector<std::uint8_t>> bytes = encodeJpeg(image, quality);
    if (!bytes) return bytes.status();
    return writeFileBytes(path, *bytes);
}

}  // namespace mvr::composite

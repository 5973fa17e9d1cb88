// High-dynamic-range environment maps (radiance.h): Radiance RGBE and OpenEXR.
//
// RGBE is decoded here rather than by stb_image: stb_image 2.27 (Debian 12) loops forever on a
// truncated run-length scanline of a Radiance file (CVE-2021-42715), and mvr already declines it
// for untrusted files (scene_io.cpp, loadSky). The format is Greg Ward's (Graphics Gems II,
// "Real Pixels"; the Radiance reference's color.c): a text header ending in an empty line, a
// resolution line, then scanlines of 4-byte RGBE texels, each flat or run-length-encoded per
// channel. EXR goes through OpenEXR (Debian's libopenexr-dev, already mvr::io's for depth).
#include "radiance.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <exception>
#include <string_view>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <fmt/core.h>

#include "mvr/core/input_file.h"

namespace mvr::detail {
namespace {

/// At most this many texels (8192 × 4096: 400 MB of floats), checked before allocating.
constexpr std::int64_t kMaxTexels = std::int64_t(kMaxEnvironmentTexels);

glm::vec3 rgbeToFloat(const std::uint8_t* p) {
    if (p[3] == 0) return glm::vec3(0.0f);
    const float f = std::ldexp(1.0f, int(p[3]) - (128 + 8));
    return glm::vec3(float(p[0]) * f, float(p[1]) * f, float(p[2]) * f);
}

}  // namespace

bool isRadianceBytes(std::span<const std::uint8_t> head) {
    auto starts = [&](std::string_view s) {
        return head.size() >= s.size() && std::memcmp(head.data(), s.data(), s.size()) == 0;
    };
    return starts("#?RADIANCE") || starts("#?RGBE");
}

bool isExrBytes(std::span<const std::uint8_t> head) {
    return head.size() >= 4 && head[0] == 0x76 && head[1] == 0x2f && head[2] == 0x31 &&
           head[3] == 0x01;
}

Result<RadianceMap> decodeRadiance(std::span<const std::uint8_t> bytes, const std::string& what) {
    std::size_t pos = 0;
    auto readLine = [&](std::string& line) {
        line.clear();
        while (pos < bytes.size() && bytes[pos] != '\n') {
            if (line.size() > 4096) return false;
            line.push_back(char(bytes[pos++]));
        }
        if (pos >= bytes.size()) return false;
        ++pos;
        if (!line.empty() && line.back() == '\r') line.pop_back();  // written on Windows
        return true;
    };
    std::string line;
    if (!readLine(line) || !isRadianceBytes(std::span(reinterpret_cast<const std::uint8_t*>(line.data()), line.size())))
        return inputError(fmt::format("{}: not a Radiance file (no '#?RADIANCE' line)", what));
    bool rgbe = true;
    for (int n = 0;; ++n) {
        if (n > 1000 || !readLine(line)) {
            return inputError(fmt::format(
                "{}: the header does not end (no empty line within 1000 lines of 4 KiB)", what));
        }
        if (line.empty()) break;
        if (line.rfind("FORMAT=", 0) == 0) rgbe = line == "FORMAT=32-bit_rle_rgbe";
    }
    if (!rgbe) {
        return inputError(fmt::format(
            "{}: only FORMAT=32-bit_rle_rgbe is read (not XYZE or another format)", what));
    }
    if (!readLine(line))
        return inputError(fmt::format("{}: no resolution line after the header", what));
    // "-Y H +X W", tokens separated by blanks (std::from_chars: no overflow).
    int h = 0, w = 0;
    bool parsed = false;
    {
        std::string_view rest(line);
        auto token = [&]() {
            while (!rest.empty() && (rest.front() == ' ' || rest.front() == '\t')) rest.remove_prefix(1);
            std::size_t n = 0;
            while (n < rest.size() && rest[n] != ' ' && rest[n] != '\t') ++n;
            const std::string_view t = rest.substr(0, n);
            rest.remove_prefix(n);
            return t;
        };
        auto number = [](std::string_view t, int& out) {
            const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), out);
            return ec == std::errc() && p == t.data() + t.size();
        };
        parsed = token() == "-Y" && number(token(), h) && token() == "+X" && number(token(), w) &&
                 token().empty();
    }
    if (!parsed) {
        return inputError(fmt::format(
            "{}: resolution '{}' is not '-Y H +X W' (the only orientation read: rows top down)",
            what, line.substr(0, 40)));
    }
    if (w < 1 || h < 1 || std::int64_t(w) * h > kMaxTexels) {
        return inputError(
            fmt::format("{}: {}x{} texels: out of range (at most {} texels)", what, w, h, kMaxTexels));
    }
    // The least a scanline takes (flat: 4 w; run-length: its 4-byte head and a run of at most
    // 127 bytes per 2 bytes in each channel): the file must be able to hold h of them before
    // w · h texels are allocated.
    const std::uint64_t leastRow =
        w >= 8 && w < 0x8000 ? std::min<std::uint64_t>(4u * std::uint64_t(w), 4u + 8u * ((std::uint64_t(w) + 126u) / 127u))
                             : 4u * std::uint64_t(w);
    if (std::uint64_t(bytes.size() - pos) < leastRow * std::uint64_t(h)) {
        return inputError(fmt::format(
            "{}: {} bytes cannot hold {} scanlines of {} texels (the file ends early)", what,
            bytes.size() - pos, h, w));
    }
    RadianceMap map;
    map.width = w, map.height = h;
    map.texels.resize(std::size_t(w) * std::size_t(h));
    std::vector<std::uint8_t> row(std::size_t(w) * 4);
    auto truncated = [&](int y) {
        return inputError(fmt::format("{}: scanline {} of {}: the file ends early", what, y, h));
    };
    for (int y = 0; y < h; ++y) {
        if (pos + 4 > bytes.size()) return truncated(y);
        const std::uint8_t* p = bytes.data() + pos;
        const bool rle = w >= 8 && w < 0x8000 && p[0] == 2 && p[1] == 2 && !(p[2] & 0x80);
        if (rle) {
            if ((int(p[2]) << 8 | int(p[3])) != w) {
                return inputError(fmt::format("{}: scanline {}: its length {} is not the width {}",
                                              what, y, int(p[2]) << 8 | int(p[3]), w));
            }
            pos += 4;
            for (int c = 0; c < 4; ++c) {
                int x = 0;
                while (x < w) {
                    if (pos >= bytes.size()) return truncated(y);
                    int count = bytes[pos++];
                    if (count > 128) {  // a run of one value
                        count -= 128;
                        if (count > w - x || pos >= bytes.size()) {
                            return inputError(fmt::format(
                                "{}: scanline {}: a run goes past the row's end", what, y));
                        }
                        const std::uint8_t v = bytes[pos++];
                        for (int k = 0; k < count; ++k) row[std::size_t(x++) * 4 + c] = v;
                    } else {  // count literal values (0 is malformed: it would never advance)
                        if (count == 0) {
                            return inputError(fmt::format(
                                "{}: scanline {}: a run of length 0", what, y));
                        }
                        if (count > w - x) {
                            return inputError(fmt::format(
                                "{}: scanline {}: a run goes past the row's end", what, y));
                        }
                        if (pos + std::size_t(count) > bytes.size()) return truncated(y);
                        for (int k = 0; k < count; ++k) row[std::size_t(x++) * 4 + c] = bytes[pos++];
                    }
                }
            }
        } else {  // flat RGBE texels
            if (pos + row.size() > bytes.size()) return truncated(y);
            std::memcpy(row.data(), bytes.data() + pos, row.size());
            pos += row.size();
        }
        for (int x = 0; x < w; ++x)
            map.texels[std::size_t(y) * std::size_t(w) + std::size_t(x)] =
                rgbeToFloat(row.data() + std::size_t(x) * 4);
    }
    return map;
}

Result<RadianceMap> readExrRadiance(const std::filesystem::path& path, const std::string& what) {
    if (Status s = checkRegularFile(path, what); !s) return s;
    try {
        Imf::InputFile file(path.c_str(), 1);
        const Imath::Box2i dw = file.header().dataWindow();
        const std::int64_t w = std::int64_t(dw.max.x) - dw.min.x + 1;
        const std::int64_t h = std::int64_t(dw.max.y) - dw.min.y + 1;
        if (w < 1 || h < 1 || w * h > kMaxTexels) {
            return inputError(fmt::format("{}: {}x{} texels: out of range (at most {} texels)",
                                          what, w, h, kMaxTexels));
        }
        const Imf::ChannelList& channels = file.header().channels();
        if (channels.findChannel("RY") || channels.findChannel("BY")) {
            return inputError(fmt::format(
                "{}: a luminance-chroma OpenEXR (RY, BY channels) is not read; save it as RGB",
                what));
        }
        const bool grey = !channels.findChannel("R") && !channels.findChannel("G") &&
                          !channels.findChannel("B") && channels.findChannel("Y");
        if (!grey && !channels.findChannel("R") && !channels.findChannel("G") &&
            !channels.findChannel("B")) {
            return inputError(fmt::format("{}: no R, G, B or Y channel", what));
        }
        std::vector<float> planes[3];
        Imf::FrameBuffer frame;
        const char* names[3] = {"R", "G", "B"};
        for (int c = 0; c < (grey ? 1 : 3); ++c) {
            planes[c].assign(std::size_t(w * h), 0.0f);
            char* base = reinterpret_cast<char*>(planes[c].data()) -
                         (std::ptrdiff_t(dw.min.x) + std::ptrdiff_t(dw.min.y) * w) *
                             std::ptrdiff_t(sizeof(float));
            frame.insert(grey ? "Y" : names[c],
                         Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * std::size_t(w),
                                    1, 1, 0.0));
        }
        file.setFrameBuffer(frame);
        file.readPixels(dw.min.y, dw.max.y);
        RadianceMap map;
        map.width = int(w), map.height = int(h);
        map.texels.resize(std::size_t(w * h));
        for (std::size_t k = 0; k < map.texels.size(); ++k) {
            map.texels[k] = grey ? glm::vec3(planes[0][k])
                                 : glm::vec3(planes[0][k], planes[1][k], planes[2][k]);
        }
        return map;
    } catch (const std::exception& e) {
        return inputError(fmt::format("{}: not a readable OpenEXR file ({})", what, e.what()));
    }
}

}  // namespace mvr::detail

#include "mvr/composite/layout.h"

#include <cstring>

#include <fmt/core.h>

namespace mvr::composite {
namespace {

constexpr Rgba8 kBlank{0, 0, 0, 255};

void copyRow(Image& dst, int dstX, int dstY, const Image& src, int srcY) {
    std::memcpy(dst.row(dstY) + static_cast<std::size_t>(dstX) * 4, src.row(srcY),
                static_cast<std::size_t>(src.width) * 4);
}

std::uint8_t avg(std::uint8_t a, std::uint8_t b) {
    return static_cast<std::uint8_t>((a + b + 1) / 2);
}

// Writes `src` squeezed to half its width at (dstX, 0) of dst.
void blitHalfWidth(Image& dst, int dstX, const Image& src) {
    const int halfW = src.width / 2;
    for (int y = 0; y < src.height; ++y) {
        const std::uint8_t* s = src.row(y);
        std::uint8_t* d = dst.row(y) + static_cast<std::size_t>(dstX) * 4;
        for (int x = 0; x < halfW; ++x)
            for (int c = 0; c < 4; ++c) d[x * 4 + c] = avg(s[x * 8 + c], s[x * 8 + 4 + c]);
    }
}

// Writes `src` squeezed to half its height at (0, dstY) of dst.
void blitHalfHeight(Image& dst, int dstY, const Image& src) {
    const int halfH = src.height / 2;
    const std::size_t rowBytes = static_cast<std::size_t>(src.width) * 4;
    for (int y = 0; y < halfH; ++y) {
        const std::uint8_t* a = src.row(2 * y);
        const std::uint8_t* b = src.row(2 * y + 1);
        std::uint8_t* d = dst.row(dstY + y);
        for (std::size_t i = 0; i < rowBytes; ++i) d[i] = avg(a[i], b[i]);
    }
}

}  // namespace

Status validatePair(const Image& a, const Image& b, const char* who) {
    if (a.empty() || b.empty())
        return usageError(fmt::format("{}: view {} is empty (expected a non-empty image)", who,
                                      a.empty() ? 0 : 1));
    if (a.width != b.width || a.height != b.height)
        return usageError(
            fmt::format("{}: views differ in size: view 0 is {}x{}, view 1 is "
                        "{}x{} (expected one size)",
                        who, a.width, a.height, b.width, b.height));
    return Status::ok();
}

Status validateViews(std::span<const Image> views, int minViews, int maxViews, const char* who) {
    const int n = static_cast<int>(views.size());
    if (n < minViews || n > maxViews) {
        std::string expected;
        if (minViews == maxViews)
            expected = fmt::format("{}", minViews);
        else if (maxViews >= (1 << 20))
            expected = fmt::format("at least {}", minViews);
        else
            expected = fmt::format("{} to {}", minViews, maxViews);
        return usageError(fmt::format("{}: needs {} view{} (got {})", who, expected,
                                      (minViews == 1 && maxViews == 1) ? "" : "s", n));
    }
    for (int i = 0; i < n; ++i) {
        const Image& v = views[static_cast<std::size_t>(i)];
        if (v.empty())
            return usageError(
                fmt::format("{}: view {} is empty (expected a non-empty image)", who, i));
        if (v.rgba.size() != static_cast<std::size_t>(v.width) * v.height * 4)
            return usageError(
                fmt::format("{}: view {} holds {} bytes for {}x{} RGBA8 "
                            "(expected {})",
                            who, i, v.rgba.size(), v.width, v.height,
                            static_cast<std::size_t>(v.width) * v.height * 4));
        if (v.width != views[0].width || v.height != views[0].height)
            return usageError(
                fmt::format("{}: views differ in size: view 0 is {}x{}, view {} "
                            "is {}x{} (expected one size)",
                            who, views[0].width, views[0].height, i, v.width, v.height));
    }
    return Status::ok();
}

Result<Image> sideBySide(const Image& first, const Image& second, bool half) {
    const char* who = half ? "mvr::composite::sideBySide(half)" : "mvr::composite::sideBySide()";
    if (Status s = validatePair(first, second, who); !s) return s;
    const int w = first.width, h = first.height;
    if (!half) {
        Image out(2 * w, h);
        for (int y = 0; y < h; ++y) {
            copyRow(out, 0, y, first, y);
            copyRow(out, w, y, second, y);
        }
        return out;
    }
    if (w % 2 != 0)
        return usageError(
            fmt::format("{}: view width {} is odd (expected an even width to "
                        "squeeze 2:1)",
                        who, w));
    Image out(w, h);
    blitHalfWidth(out, 0, first);
    blitHalfWidth(out, w / 2, second);
    return out;
}

Result<Image> topBottom(const Image& top, const Image& bottom, bool half) {
    const char* who = half ? "mvr::composite::topBottom(half)" : "mvr::composite::topBottom()";
    if (Status s = validatePair(top, bottom, who); !s) return s;
    const int w = top.width, h = top.height;
    if (!half) {
        Image out(w, 2 * h);
        for (int y = 0; y < h; ++y) {
            copyRow(out, 0, y, top, y);
            copyRow(out, 0, h + y, bottom, y);
        }
        return out;
    }
    if (h % 2 != 0)
        return usageError(
            fmt::format("{}: view height {} is odd (expected an even height to "
                        "squeeze 2:1)",
                        who, h));
    Image out(w, h);
    blitHalfHeight(out, 0, top);
    blitHalfHeight(out, h / 2, bottom);
    return out;
}

Result<Image> interleaveRows(std::span<const Image> views) {
    if (Status s = validateViews(views, 2, 1 << 20, "mvr::composite::interleaveRows()"); !s)
        return s;
    const std::size_t n = views.size();
    Image out(views[0].width, views[0].height);
    for (int y = 0; y < out.height; ++y) copyRow(out, 0, y, views[y % n], y);
    return out;
}

Result<Image> interleaveColumns(std::span<const Image> views) {
    if (Status s = validateViews(views, 2, 1 << 20, "mvr::composite::interleaveColumns()"); !s)
        return s;
    const std::size_t n = views.size();
    Image out(views[0].width, views[0].height);
    for (int y = 0; y < out.height; ++y) {
        std::uint8_t* d = out.row(y);
        for (int x = 0; x < out.width; ++x) std::memcpy(d + x * 4, views[x % n].row(y) + x * 4, 4);
    }
    return out;
}

Result<Image> checkerboard(const Image& first, const Image& second) {
    if (Status s = validatePair(first, second, "mvr::composite::checkerboard()"); !s) return s;
    Image out(first.width, first.height);
    for (int y = 0; y < out.height; ++y) {
        std::uint8_t* d = out.row(y);
        for (int x = 0; x < out.width; ++x) {
            const Image& src = ((x + y) % 2 == 0) ? first : second;
            std::memcpy(d + x * 4, src.row(y) + x * 4, 4);
        }
    }
    return out;
}

int hdmiActiveSpaceLines(int width, int height) {
    // HDMI 1.4a, 3D structure "frame packing", progressive formats: the active space between
    // the left and right frames equals the vertical blanking of the 2D timing (CEA-861:
    // 720p 30 lines, 1080p 45 lines).
    if (width == 1280 && height == 720) return 30;
    if (width == 1920 && height == 1080) return 45;
    return -1;
}

Result<Image> hdmiFramePacking(const Image& left, const Image& right) {
    const char* who = "mvr::composite::hdmiFramePacking()";
    if (Status s = validatePair(left, right, who); !s) return s;
    const int gap = hdmiActiveSpaceLines(left.width, left.height);
    if (gap < 0)
        return usageError(
            fmt::format("{}: view size {}x{} has no HDMI 1.4a frame packing "
                        "(expected 1280x720 or 1920x1080)",
                        who, left.width, left.height));
    Image out(left.width, 2 * left.height + gap, kBlank);
    for (int y = 0; y < left.height; ++y) {
        copyRow(out, 0, y, left, y);
        copyRow(out, 0, left.height + gap + y, right, y);
    }
    return out;
}

Result<Image> quilt(std::span<const Image> views, int columns, int rows) {
    const char* who = "mvr::composite::quilt()";
    if (Status s = validateViews(views, 1, 1 << 20, who); !s) return s;
    if (columns < 1 || rows < 1)
        return usageError(
            fmt::format("{}: grid {}x{} (expected columns and rows >= 1)", who, columns, rows));
    const int n = static_cast<int>(views.size());
    if (static_cast<long long>(columns) * rows < n)
        return usageError(
            fmt::format("{}: grid {}x{} has {} tiles for {} views (expected at "
                        "least one tile per view)",
                        who, columns, rows, columns * rows, n));
    const int w = views[0].width, h = views[0].height;
    if (static_cast<long long>(columns) * w > 65536 || static_cast<long long>(rows) * h > 65536)
        return usageError(
            fmt::format("{}: quilt of {}x{} tiles of {}x{} is larger than "
                        "65536 pixels on a side",
                        who, columns, rows, w, h));
    Image out(columns * w, rows * h, kBlank);
    for (int i = 0; i < n; ++i) {
        const int tileX = i % columns;
        const int tileRowFromBottom = i / columns;
        const int y0 = (rows - 1 - tileRowFromBottom) * h;
        for (int y = 0; y < h; ++y) copyRow(out, tileX * w, y0 + y, views[i], y);
    }
    return out;
}

}  // namespace mvr::composite

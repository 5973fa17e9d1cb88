#include "mvr/composite/compose.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>

#include <fmt/core.h>

#include "mvr/composite/anaglyph.h"
#include "mvr/composite/jpeg.h"
#include "mvr/composite/layout.h"
#include "mvr/composite/lenticular.h"
#include "mvr/composite/rgbd.h"
#include "mvr/io/png.h"

namespace mvr::composite {
namespace {

constexpr int kAny = kAnyViewCount;

// Cells of the Tiled rule: {rule, cellsAcross, cellsDown, squeezeX, squeezeY}.
constexpr FormatSize kOneCell{SizeRule::Tiled, 1, 1, 1, 1};
constexpr FormatSize kSideBySide{SizeRule::Tiled, 2, 1, 1, 1};
constexpr FormatSize kSideBySideHalf{SizeRule::Tiled, 2, 1, 2, 1};
constexpr FormatSize kTopBottom{SizeRule::Tiled, 1, 2, 1, 1};
constexpr FormatSize kTopBottomHalf{SizeRule::Tiled, 1, 2, 1, 2};

// The composers of the built-in rows (FormatInfo::composer): views checked and in order.
Result<std::pair<int, int>> quiltGridFor(std::span<const Image> views,
                                         const ComposeOptions& options, const char* who);

template <AnaglyphMethod M>
Result<Image> composeAnaglyph(std::span<const Image> v, const ComposeOptions&,
                              const std::string&) {
    return anaglyph(v[0], v[1], M);
}
Result<Image> composeSbs(std::span<const Image> v, const ComposeOptions& options,
                         const std::string&) {
    const bool rightFirst = options.crossEyed;
    return sideBySide(v[rightFirst ? 1 : 0], v[rightFirst ? 0 : 1], false);
}
Result<Image> composeSbsHalf(std::span<const Image> v, const ComposeOptions& options,
                             const std::string&) {
    const bool rightFirst = options.crossEyed;
    return sideBySide(v[rightFirst ? 1 : 0], v[rightFirst ? 0 : 1], true);
}
Result<Image> composeTb(std::span<const Image> v, const ComposeOptions&, const std::string&) {
    return topBottom(v[0], v[1], false);
}
Result<Image> composeTbHalf(std::span<const Image> v, const ComposeOptions&, const std::string&) {
    return topBottom(v[0], v[1], true);
}
Result<Image> composeRows(std::span<const Image> v, const ComposeOptions&, const std::string&) {
    return interleaveRows(v);
}
Result<Image> composeColumns(std::span<const Image> v, const ComposeOptions&,
                             const std::string&) {
    return interleaveColumns(v);
}
Result<Image> composeCheckerboard(std::span<const Image> v, const ComposeOptions&,
                                  const std::string&) {
    return checkerboard(v[0], v[1]);
}
Result<Image> composeFramePacking(std::span<const Image> v, const ComposeOptions&,
                                  const std::string&) {
    return hdmiFramePacking(v[0], v[1]);
}
Result<Image> composeQuilt(std::span<const Image> v, const ComposeOptions& options,
                           const std::string& who) {
    Result<std::pair<int, int>> grid = quiltGridFor(v, options, who.c_str());
    if (!grid) return grid.status();
    return quilt(v, grid->first, grid->second);
}
Result<Image> composeLenticular(std::span<const Image> v, const ComposeOptions& options,
                                const std::string&) {
    return lenticular(v, options.lenticular);
}
// jps: the side-by-side picture of its file, right view on the left.
Result<Image> composeJps(std::span<const Image> v, const ComposeOptions&, const std::string&) {
    return sideBySide(v[1], v[0], false);
}

const std::array kBuiltinFormats = {
    FormatInfo{"anaglyph-dubois", 2, 2, false, ".png",
               "red-cyan, Dubois least squares (the default anaglyph)", kOneCell, FileKind::Png, composeAnaglyph<AnaglyphMethod::Dubois>, GpuPlan::Anaglyph},
    FormatInfo{"anaglyph-color", 2, 2, false, ".png", "red-cyan, full color", kOneCell, FileKind::Png, composeAnaglyph<AnaglyphMethod::Color>, GpuPlan::Anaglyph},
    FormatInfo{"anaglyph-half-color", 2, 2, false, ".png", "red-cyan, left eye as luminance",
               kOneCell, FileKind::Png, composeAnaglyph<AnaglyphMethod::HalfColor>, GpuPlan::Anaglyph},
    FormatInfo{"anaglyph-gray", 2, 2, false, ".png", "red-cyan, luminance only", kOneCell, FileKind::Png, composeAnaglyph<AnaglyphMethod::Gray>, GpuPlan::Anaglyph},
    FormatInfo{"anaglyph-true", 2, 2, false, ".png", "red-blue, luminance (true anaglyph)",
               kOneCell, FileKind::Png, composeAnaglyph<AnaglyphMethod::True>, GpuPlan::Anaglyph},
    FormatInfo{"anaglyph-dubois-gm", 2, 2, false, ".png", "green-magenta, Dubois least squares",
               kOneCell, FileKind::Png, composeAnaglyph<AnaglyphMethod::DuboisGreenMagenta>, GpuPlan::Anaglyph},
    FormatInfo{"anaglyph-dubois-ab", 2, 2, false, ".png", "amber-blue, Dubois least squares",
               kOneCell, FileKind::Png, composeAnaglyph<AnaglyphMethod::DuboisAmberBlue>, GpuPlan::Anaglyph},
    FormatInfo{"sbs", 2, 2, false, ".png", "side by side, full width (2W x H)", kSideBySide, FileKind::Png, composeSbs, GpuPlan::SideBySide},
    FormatInfo{"sbs-half", 2, 2, false, ".png", "side by side, squeezed (W x H)", kSideBySideHalf, FileKind::Png, composeSbsHalf, GpuPlan::SideBySideHalf},
    FormatInfo{"tb", 2, 2, false, ".png", "top-bottom, left on top (W x 2H)", kTopBottom, FileKind::Png, composeTb, GpuPlan::TopBottom},
    FormatInfo{"tb-half", 2, 2, false, ".png", "top-bottom, squeezed (W x H)", kTopBottomHalf, FileKind::Png, composeTbHalf, GpuPlan::TopBottomHalf},
    FormatInfo{"rows", 2, kAny, false, ".png", "row-interleaved: row y from view y mod N",
               kOneCell, FileKind::Png, composeRows, GpuPlan::Rows},
    FormatInfo{"columns", 2, kAny, false, ".png",
               "column-interleaved: column x from view x mod N (parallax barrier)", kOneCell, FileKind::Png, composeColumns, GpuPlan::Columns},
    FormatInfo{"checkerboard", 2, 2, false, ".png", "checkerboard: (x + y) even from the left",
               kOneCell, FileKind::Png, composeCheckerboard, GpuPlan::Checkerboard},
    FormatInfo{"hdmi-frame-packing",
               2,
               2,
               false,
               ".png",
               "HDMI 1.4a frame packing: 720p -> 1280x1470, 1080p -> 1920x2205",
               {SizeRule::FramePacked}, FileKind::Png, composeFramePacking, GpuPlan::FramePacking},
    FormatInfo{"quilt",
               1,
               kAny,
               false,
               ".png",
               "Looking Glass quilt, view 0 bottom left: quilt_qsCxRaA.png",
               {SizeRule::QuiltGrid}, FileKind::Png, composeQuilt, GpuPlan::Quilt},
    FormatInfo{"lenticular",
               2,
               kAny,
               false,
               ".png",
               "slanted-lens sub-pixel interleave from a panel calibration",
               {SizeRule::Panel}, FileKind::Png, composeLenticular, GpuPlan::Lenticular},
    FormatInfo{"jps", 2, 2, false, ".jps", "JPEG side by side, right view on the left",
               kSideBySide, FileKind::Jps, composeJps, GpuPlan::None},
    FormatInfo{"mpo",
               2,
               4096,
               true,
               ".mpo",
               "CIPA multi-picture JPEG, one image per view",
               {SizeRule::PerView}, FileKind::Mpo, nullptr, GpuPlan::None},
    FormatInfo{"rgbd",
               2,
               2,
               false,
               ".png",
               "Looking Glass RGB-D: colour and depth (white = near) side by side + rgbd.json",
               {SizeRule::ColourDepth}, FileKind::Png, composeRgbd, GpuPlan::None, true},
};

// As composite::quilt(): no side of a quilt beyond this.
constexpr long long kMaxQuiltSide = 65536;

std::string lower(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

// The views in the order the format should use them: reversed for swapEyes.
struct Ordered {
    std::span<const Image> span;
    std::vector<Image> storage;
};

Ordered ordered(std::span<const Image> views, bool reverse) {
    Ordered o;
    if (!reverse) {
        o.span = views;
        return o;
    }
    o.storage.assign(views.rbegin(), views.rend());
    o.span = o.storage;
    return o;
}

// The quilt grid compose() uses: the options' or chooseQuiltLayout()'s.
Result<std::pair<int, int>> quiltGrid(int viewCount, int viewWidth, int viewHeight,
                                      const ComposeOptions& options, const std::string& who) {
    if ((options.quiltColumns == 0) != (options.quiltRows == 0) || options.quiltColumns < 0 ||
        options.quiltRows < 0)
        return usageError(
            fmt::format("{}: quilt grid {}x{} (expected both columns and rows >= 1, "
                        "or both 0 for automatic)",
                        who, options.quiltColumns, options.quiltRows));
    if (options.quiltColumns > 0) return std::pair{options.quiltColumns, options.quiltRows};
    return chooseQuiltLayout(viewCount, viewWidth, viewHeight);
}

Result<std::pair<int, int>> quiltGridFor(std::span<const Image> views,
                                         const ComposeOptions& options, const char* who) {
    return quiltGrid(static_cast<int>(views.size()), views[0].width, views[0].height, options, who);
}

// "needs 2 views (got 3)", as validateViews() words it.
Status checkViewCount(const FormatInfo& f, int viewCount, const std::string& who) {
    if (viewCount >= f.minViews && viewCount <= f.maxViews) return Status::ok();
    std::string expected;
    if (f.minViews == f.maxViews)
        expected = fmt::format("{}", f.minViews);
    else if (f.maxViews >= kAny)
        expected = fmt::format("at least {}", f.minViews);
    else
        expected = fmt::format("{} to {}", f.minViews, f.maxViews);
    return usageError(fmt::format("{}: needs {} view{} (got {})", who, expected,
                                  (f.minViews == 1 && f.maxViews == 1) ? "" : "s", viewCount));
}

// The formats table: the built-in rows, then those registerFormat() added.
std::vector<FormatInfo>& table() {
    static std::vector<FormatInfo> rows(kBuiltinFormats.begin(), kBuiltinFormats.end());
    return rows;
}

}  // namespace

std::span<const FormatInfo> formats() { return table(); }

Status registerFormat(const FormatInfo& format) {
    const std::string who = fmt::format("mvr::composite::registerFormat(): '{}'", format.name);
    if (format.name.empty()) return usageError(who + ": a format needs a name");
    for (const FormatInfo& f : table())
        if (f.name == format.name) return usageError(who + ": the name is taken");
    if (format.minViews < 1 || format.maxViews < format.minViews)
        return usageError(fmt::format("{}: views {}..{} (expected 1 <= min <= max)", who,
                                      format.minViews, format.maxViews));
    if (format.file == FileKind::Mpo || format.fileOnly)
        return usageError(who + ": only image formats (FileKind::Png / Jps) can be registered");
    if (!format.composer) return usageError(who + ": an image format needs a composer");
    if (format.gpu != GpuPlan::None)
        return usageError(who + ": a registered format has no GPU plan (GpuPlan::None)");
    table().push_back(format);
    return Status::ok();
}

std::vector<std::string> formatNames() {
    std::vector<std::string> names;
    for (const FormatInfo& f : table()) names.emplace_back(f.name);
    return names;
}

Result<FormatInfo> findFormat(std::string_view name) {
    for (const FormatInfo& f : table())
        if (f.name == name) return f;
    std::string all;
    for (const FormatInfo& f : table()) all += (all.empty() ? "" : ", ") + std::string(f.name);
    return usageError(fmt::format("unknown output format '{}' (expected one of: {})", name, all));
}

std::string formatHelp() {
    std::string out;
    for (const FormatInfo& f : table()) {
        const std::string views = f.minViews == f.maxViews ? fmt::format("{} views", f.minViews)
                                  : f.maxViews >= kAny
                                      ? fmt::format("{}+ views", f.minViews)
                                      : fmt::format("{}-{} views", f.minViews, f.maxViews);
        out += fmt::format("  {:<20} {:<12} {}\n", f.name, views, f.summary);
    }
    return out;
}

std::pair<int, int> chooseQuiltLayout(int viewCount, int viewWidth, int viewHeight) {
    MVR_ASSERT(viewCount >= 1 && viewWidth >= 1 && viewHeight >= 1);
    std::pair<int, int> best{viewCount, 1};
    double bestCost = 1e300;
    int bestBlank = 0;
    for (int rows = 1; rows <= viewCount; ++rows) {
        const int columns = (viewCount + rows - 1) / rows;
        if ((rows - 1) * columns >= viewCount) continue;  // an empty row
        const double aspect = (double(columns) * viewWidth) / (double(rows) * viewHeight);
        const double cost = std::abs(std::log(aspect));
        const int blank = columns * rows - viewCount;
        if (cost < bestCost - 1e-9 || (std::abs(cost - bestCost) <= 1e-9 && blank < bestBlank)) {
            best = {columns, rows};
            bestCost = cost;
            bestBlank = blank;
        }
    }
    return best;
}

std::string formatAspect(int width, int height) {
    std::string s = fmt::format("{:.4f}", double(width) / double(height));
    while (!s.empty() && s.back() == '0') s.pop_back();
    if (!s.empty() && s.back() == '.') s.pop_back();
    return s;
}

Result<std::pair<int, int>> parseQuiltGrid(std::string_view text) {
    const std::string t(text);
    int c = 0, r = 0;
    char x = 0, extra = 0;
    if (std::sscanf(t.c_str(), "%d%c%d%c", &c, &x, &r, &extra) != 3 || (x != 'x' && x != 'X') ||
        c < 1 || r < 1 || c > 256 || r > 256 || t.find_first_of("+- ") != std::string::npos)
        return usageError(
            fmt::format("--quilt '{}': expected CxR with 1..256 columns and rows, e.g. 8x6", t));
    return std::pair{c, r};
}

double convergenceAngleDegrees(double interaxial, double convergenceDistance) {
    if (!(convergenceDistance > 0) || !std::isfinite(convergenceDistance) ||
        !std::isfinite(interaxial))
        return 0.0;
    return 2.0 * std::atan(interaxial / (2.0 * convergenceDistance)) * 180.0 / std::numbers::pi;
}

/// layout.h's texts for a view side that a -half format cannot squeeze `by`:1.
static Status squeezeError(const std::string& who, const char* side, int value, int by) {
    return usageError(by == 2 ? fmt::format("{}: view {} {} is odd (expected an even {} to squeeze "
                                            "2:1)",
                                            who, side, value, side)
                              : fmt::format("{}: view {} {} (expected a multiple of {} to squeeze "
                                            "{}:1)",
                                            who, side, value, by, by));
}

Result<Size> outputSize(const FormatInfo& f, int viewCount, int w, int h,
                        const ComposeOptions& options, const std::string& who) {
    if (Status s = checkViewCount(f, viewCount, who); !s) return s;
    if (w < 1 || h < 1)
        return usageError(fmt::format("{}: view size {}x{} (expected at least 1x1)", who, w, h));
    const FormatSize& rule = f.size;
    switch (rule.rule) {
        case SizeRule::Tiled:
            // layout.h's texts for the -half formats.
            if (w % rule.squeezeX != 0) return squeezeError(who, "width", w, rule.squeezeX);
            if (h % rule.squeezeY != 0) return squeezeError(who, "height", h, rule.squeezeY);
            return Size{rule.cellsAcross * (w / rule.squeezeX),
                        rule.cellsDown * (h / rule.squeezeY)};
        case SizeRule::FramePacked: {
            const int gap = hdmiActiveSpaceLines(w, h);
            if (gap < 0)
                return usageError(
                    fmt::format("{}: view size {}x{} has no HDMI 1.4a frame packing "
                                "(expected 1280x720 or 1920x1080)",
                                who, w, h));
            return Size{w, 2 * h + gap};
        }
        case SizeRule::QuiltGrid: {
            Result<std::pair<int, int>> grid = quiltGrid(viewCount, w, h, options, who);
            if (!grid) return grid.status();
            const auto [columns, rows] = *grid;
            if (static_cast<long long>(columns) * rows < viewCount)
                return usageError(fmt::format(
                    "{}: grid {}x{} has {} tiles for {} views (expected at "
                    "least one tile per view)",
                    who, columns, rows, static_cast<long long>(columns) * rows, viewCount));
            if (static_cast<long long>(columns) * w > kMaxQuiltSide ||
                static_cast<long long>(rows) * h > kMaxQuiltSide)
                return usageError(
                    fmt::format("{}: quilt of {}x{} tiles of {}x{} is larger than "
                                "65536 pixels on a side",
                                who, columns, rows, w, h));
            return Size{columns * w, rows * h};
        }
        case SizeRule::Panel: {
            const LenticularCalibration& cal = options.lenticular;
            const Size panel{cal.screenWidth > 0 ? cal.screenWidth : w,
                             cal.screenHeight > 0 ? cal.screenHeight : h};
            Result<LenticularShaderParams> params =
                lenticularShaderParams(cal, panel.width, panel.height);
            if (!params) return params.status();
            return panel;
        }
        case SizeRule::PerView: return Size{w, h};
        case SizeRule::ColourDepth:
            if (options.rgbdDepth == DepthPosition::Right || options.rgbdDepth == DepthPosition::Left)
                return Size{2 * w, h};
            return Size{w, 2 * h};
    }
    return internalError(fmt::format("{}: format without a size rule", who));
}

Result<Size> outputSize(std::string_view format, int viewCount, int viewWidth, int viewHeight,
                        const ComposeOptions& options) {
    Result<FormatInfo> info = findFormat(format);
    if (!info) return info.status();
    return outputSize(*info, viewCount, viewWidth, viewHeight, options,
                      fmt::format("mvr::composite::outputSize(): {}", info->name));
}

Result<Size> largestViewSize(std::string_view format, int viewCount, int frameWidth,
                             int frameHeight, const ComposeOptions& options) {
    Result<FormatInfo> info = findFormat(format);
    if (!info) return info.status();
    const std::string who = fmt::format("mvr::composite::largestViewSize(): {}", info->name);
    if (Status s = checkViewCount(*info, viewCount, who); !s) return s;
    const auto fits = [&](Size view) {
        Result<Size> out = outputSize(*info, viewCount, view.width, view.height, options, who);
        return out && out->width <= frameWidth && out->height <= frameHeight;
    };
    const auto tooSmall = [&](std::string_view needs) -> Status {
        return usageError(fmt::format("{}: a frame of {}x{} is too small (expected {})", who,
                                      frameWidth, frameHeight, needs));
    };
    const FormatSize& rule = info->size;
    switch (rule.rule) {
        case SizeRule::Tiled: {
            const Size view{frameWidth / rule.cellsAcross * rule.squeezeX,
                            frameHeight / rule.cellsDown * rule.squeezeY};
            if (view.width < 1 || view.height < 1)
                return tooSmall(fmt::format("at least {}x{}", rule.cellsAcross, rule.cellsDown));
            return view;
        }
        case SizeRule::FramePacked:
            for (const Size view : {Size{1920, 1080}, Size{1280, 720}})
                if (fits(view)) return view;
            return tooSmall("at least 1280x1470");
        case SizeRule::QuiltGrid: {
            if (Result<std::pair<int, int>> grid = quiltGrid(viewCount, 1, 1, options, who); !grid)
                return grid.status();
            // The grid is the options' or, automatic, the one chooseQuiltLayout() picks for the
            // views themselves: try every grid without an empty row and keep the largest views
            // whose own grid it is.
            std::optional<Size> best;
            for (int rows = 1; rows <= viewCount; ++rows) {
                const int columns =
                    options.quiltColumns > 0 ? options.quiltColumns : (viewCount + rows - 1) / rows;
                if (options.quiltRows > 0 && rows != options.quiltRows) continue;
                const Size view{frameWidth / columns, frameHeight / rows};
                if (view.width < 1 || view.height < 1 || !fits(view)) continue;
                if (options.quiltColumns == 0 &&
                    chooseQuiltLayout(viewCount, view.width, view.height) !=
                        std::pair{columns, rows})
                    continue;
                if (!best || static_cast<long long>(view.width) * view.height >
                                 static_cast<long long>(best->width) * best->height)
                    best = view;
            }
            if (!best) return tooSmall("one pixel per view in a quilt grid");
            return *best;
        }
        case SizeRule::Panel: {
            const LenticularCalibration& cal = options.lenticular;
            const Size view{cal.screenWidth > 0 ? cal.screenWidth : frameWidth,
                            cal.screenHeight > 0 ? cal.screenHeight : frameHeight};
            if (view.width < 1 || view.height < 1 || !fits(view))
                return tooSmall(fmt::format("the panel, {}x{}", view.width, view.height));
            return view;
        }
        case SizeRule::PerView:
            if (frameWidth < 1 || frameHeight < 1) return tooSmall("at least 1x1");
            return Size{frameWidth, frameHeight};
        case SizeRule::ColourDepth: {
            const bool across = options.rgbdDepth == DepthPosition::Right ||
                                options.rgbdDepth == DepthPosition::Left;
            const Size view{across ? frameWidth / 2 : frameWidth,
                            across ? frameHeight : frameHeight / 2};
            if (view.width < 1 || view.height < 1)
                return tooSmall(across ? "at least 2x1" : "at least 1x2");
            return view;
        }
    }
    return internalError(fmt::format("{}: format without a size rule", who));
}

Result<Image> compose(std::string_view format, std::span<const Image> views,
                      const ComposeOptions& options) {
    Result<FormatInfo> info = findFormat(format);
    if (!info) return info.status();
    const std::string who = fmt::format("mvr::composite::compose(): {}", info->name);
    if (Status s = validateViews(views, info->minViews, info->maxViews, who.c_str()); !s) return s;
    if (info->fileOnly)
        return unsupportedError(
            fmt::format("{}: a multi-image file, not one image (write it with "
                        "writeComposite(), or `mvr compose -o DIR`)",
                        who));
    if (!info->composer)
        return internalError(fmt::format("{}: format without an implementation", who));
    const Ordered o = ordered(views, options.swapEyes);
    return info->composer(o.span, options, who);
}

Result<std::string> compositeFileName(std::string_view format, std::span<const Image> views,
                                      const ComposeOptions& options) {
    Result<FormatInfo> info = findFormat(format);
    if (!info) return info.status();
    const std::string who = fmt::format("mvr::composite::compositeFileName(): {}", info->name);
    if (Status s = validateViews(views, info->minViews, info->maxViews, who.c_str()); !s) return s;
    if (info->size.rule == SizeRule::QuiltGrid) {  // the Looking Glass file name
        Result<std::pair<int, int>> grid = quiltGridFor(views, options, who.c_str());
        if (!grid) return grid.status();
        if (options.quiltAspect > 0.0) {
            std::string a = fmt::format("{:.4f}", options.quiltAspect);
            while (!a.empty() && a.back() == '0') a.pop_back();
            if (!a.empty() && a.back() == '.') a.pop_back();
            return fmt::format("quilt_qs{}x{}a{}.png", grid->first, grid->second, a);
        }
        return fmt::format("quilt_qs{}x{}a{}.png", grid->first, grid->second,
                           formatAspect(views[0].width, views[0].height));
    }
    return fmt::format("{}{}", info->name, info->extension);
}

Status writeCompositeFile(std::string_view format, std::span<const Image> views,
                          const ComposeOptions& options, const std::filesystem::path& file) {
    Result<FormatInfo> info = findFormat(format);
    if (!info) return info.status();
    const std::string ext = lower(file.extension().string());
    const std::string who = fmt::format("mvr::composite::writeCompositeFile(): {}", info->name);
    if (info->file == FileKind::Mpo) {
        if (ext != ".mpo")
            return usageError(
                fmt::format("{}: output '{}' (expected a .mpo file name)", who, file.string()));
        Result<std::vector<std::uint8_t>> bytes = encodeMpo(views, options);
        if (!bytes) return bytes.status();
        return writeFileBytes(file, *bytes);
    }
    if (info->file == FileKind::Jps) {
        if (ext != ".jps" && ext != ".jpg" && ext != ".jpeg")
            return usageError(
                fmt::format("{}: output '{}' (expected a .jps file name)", who, file.string()));
        Result<Image> picture = compose(format, views, options);
        if (!picture) return picture.status();
        Result<std::vector<std::uint8_t>> bytes = encodeJpsPicture(*picture, options.jpegQuality);
        if (!bytes) return bytes.status();
        return writeFileBytes(file, *bytes);
    }
    if (ext != ".png" && ext != ".jpg" && ext != ".jpeg")
        return usageError(fmt::format("{}: output '{}' (expected a .png, .jpg or .jpeg file name)",
                                      who, file.string()));
    Result<Image> image = compose(format, views, options);
    if (!image) return image.status();
    if (ext == ".png") return writePng(file, *image);
    return writeJpeg(file, *image, options.jpegQuality);
}

Result<std::filesystem::path> writeComposite(std::string_view format, std::span<const Image> views,
                                             const ComposeOptions& options,
                                             const std::filesystem::path& outDir) {
    Result<std::string> name = compositeFileName(format, views, options);
    if (!name) return name.status();
    std::filesystem::path path = outDir / *name;
    if (Status s = writeCompositeFile(format, views, options, path); !s) return s;
    return path;
}

Result<std::vector<Image>> readViewFile(const std::filesystem::path& path) {
    Result<std::vector<std::uint8_t>> bytes = readFileBytes(path);
    if (!bytes) return bytes.status();
    const std::vector<std::uint8_t>& d = *bytes;
    const std::string what = path.string();
    if (d.empty()) return inputError(fmt::format("{}: empty file (expected PNG or JPEG)", what));
    static constexpr std::uint8_t kPng[] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
    if (d.size() >= 8 && std::equal(std::begin(kPng), std::end(kPng), d.begin())) {
        Result<Image> image = readPng(path);
        if (!image) return image.status();
        std::vector<Image> views;
        views.push_back(std::move(*image));
        return views;
    }
    if (d.size() >= 2 && d[0] == 0xFF && d[1] == 0xD8) {
        if (lower(path.extension().string()) == ".jps") {
            Result<Image> picture = decodeJpeg(d, what);
            if (!picture) return picture.status();
            return splitJps(*picture, what);
        }
        return decodeMpo(d, what);
    }
    return inputError(fmt::format("{}: not a PNG or JPEG file (unrecognised signature)", what));
}

}  // namespace mvr::composite

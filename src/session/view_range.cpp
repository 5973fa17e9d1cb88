// src/session/view_range.cpp — --view-range A:B: the rig cut down to views A..B
// (mvr/session/view_range.h).
#include "mvr/session/view_range.h"

#include <regex>

#include <fmt/core.h>

namespace mvr::session {

Result<std::pair<int, int>> parseViewRange(const std::string& text, int viewCount) {
    static const std::regex kRange(R"(\s*(\d+)\s*:\s*(\d+)\s*)");
    std::smatch m;
    if (!std::regex_match(text, m, kRange)) {
        return usageError(fmt::format(
            "--view-range '{}' is not of the form A:B (the first and last view to render, "
            "e.g. 0:23)",
            text));
    }
    // More than 9 digits is past any view count (and past what std::stol may hold).
    auto number = [](const std::string& digits) {
        return digits.size() > 9 ? 1000000000L : std::stol(digits);
    };
    const long a = number(m[1].str()), b = number(m[2].str());
    if (a > b || b >= viewCount) {
        return usageError(fmt::format(
            "--view-range '{}' is out of range (expected 0 <= A <= B <= {}: views A..B of the "
            "rig's {})",
            text, viewCount - 1, viewCount));
    }
    return std::pair{int(a), int(b)};
}

Status restrictToViewRange(const RenderRecipe& r, Prepared& p) {
    if (r.viewRange.empty()) return {};
    auto range = parseViewRange(r.viewRange, p.rig.viewCount());
    if (!range) return range.status();
    const std::string who = fmt::format("--view-range {}", r.viewRange);
    if (p.rig.rows != 1) {
        return usageError(who + ": needs a row of views (--views N), not a --view-grid");
    }
    if (r.sequence.active()) {
        return usageError(who + ": renders a still (not with --frames, --orbit or "
                                "--camera-path; split a sequence with --frame-range or --shard)");
    }
    if (!r.outputs.formats.empty()) {
        return usageError(fmt::format(
            "{}: not with --format {} (a composite needs every view: render the ranges, then "
            "`mvr compose` their views)",
            who, r.outputs.formats.front()));
    }
    if (!r.outputs.write.empty() && p.write.composites) {
        return usageError(fmt::format(
            "{}: not with --write {} (a composite needs every view: render the ranges, then "
            "`mvr compose` their views)",
            who, r.outputs.write));
    }
    if (!p.formats.empty()) {  // a --display preset's composite
        p.notes.push_back(fmt::format(
            "note: {} writes views {}..{}, not --display {}'s {} (it needs every view)", who,
            range->first, range->second, r.display, p.formats.front()));
    }
    p.formats.clear();
    p.write.composites = false;
    if (r.outputs.write.empty()) p.write.views = true;
    // The whole rig's views A..B: the same cameras, so the same pixels. Its culling frustum
    // encloses them still (it encloses every view of the whole rig).
    p.rig.views = std::vector<View>(p.rig.views.begin() + range->first,
                                    p.rig.views.begin() + range->second + 1);
    p.rig.columns = range->second - range->first + 1;
    p.viewRange = *range;
    return {};
}

}  // namespace mvr::session

// tests/fuzz/visual_json_fuzz.cpp — a Looking Glass calibration (visual.json):
// composite::parseLookingGlassCalibration(), and what the calibration is used for —
// lenticularShaderParams() and, for screens up to 64×64 (the harness's own bound, to keep each
// run short), the lenticular interleave of two small views.
#include <cstdint>
#include <cstdlib>
#include <string_view>
#include <vector>

#include "mvr/composite/lenticular.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view json(reinterpret_cast<const char*>(data), size);
    auto cal = mvr::composite::parseLookingGlassCalibration(json, "visual.json");
    if (!cal) return 0;
    const int w = cal->screenWidth ? cal->screenWidth : 8;
    const int h = cal->screenHeight ? cal->screenHeight : 6;
    auto params = mvr::composite::lenticularShaderParams(*cal, w, h);
    if (params) {
        for (int sub = 0; sub < 3; ++sub) {
            const int v = mvr::composite::lenticularView(*params, 2, w, h, w / 2, h / 2, sub);
            if (v < 0 || v > 1) std::abort();
        }
    }
    if (w <= 64 && h <= 64) {
        const std::vector<mvr::Image> views = {mvr::Image(8, 6, {255, 0, 0, 255}),
                                               mvr::Image(8, 6, {0, 0, 255, 255})};
        auto out = mvr::composite::lenticular(views, *cal);
        if (out && (out->width != w || out->height != h)) std::abort();
    }
    return 0;
}

// The installed mvr from a consumer's side: the soft backend by name (mvr::makeBackend), the
// default scene framed as `mvr render` frames it (mvr::frameScene), one stereo pair at 64x48.
// Prints one line and exits 0 when the backend returned two drawn images of that size, and
// mvr::session prepared the same request from a RenderRecipe (the rig `mvr render` renders).
#include <cstdio>
#include <string>

#include "mvr/backends.h"
#include "mvr/core/framing.h"
#include "mvr/core/scene.h"
#include "mvr/session/prepare.h"
#include "mvr/session/render.h"

namespace {

int fail(const std::string& what) {
    std::fprintf(stderr, "error: %s\n", what.c_str());
    return 1;
}

}  // namespace

int main() {
    auto backend = mvr::makeBackend("soft", {.threads = 2});
    if (!backend) return fail("makeBackend(soft): " + backend.status().message());

    const mvr::Scene scene = mvr::makeDefaultScene();
    mvr::RenderSettings settings;
    settings.width = 64, settings.height = 48;
    auto request = mvr::frameScene(scene, mvr::FramingParams{}, settings);
    if (!request) return fail("frameScene: " + request.status().message());

    auto out =
        (*backend)->render(scene, request->rig, request->settings, (*backend)->defaultMethod());
    if (!out) return fail("render: " + out.status().message());
    if (out->color.size() != 2) {
        return fail("expected 2 images, got " + std::to_string(out->color.size()));
    }
    for (const mvr::Image& image : out->color) {
        if (image.width != 64 || image.height != 48) {
            return fail("expected 64x48 images, got " + std::to_string(image.width) + "x" +
                        std::to_string(image.height));
        }
        // Something drawn: not every pixel is the clear colour of the top-left one.
        bool drawn = false;
        for (std::size_t i = 4; i < image.rgba.size() && !drawn; i += 4) {
            for (int c = 0; c < 3; ++c) drawn |= image.rgba[i + c] != image.rgba[c];
        }
        if (!drawn) return fail("an image holds only the clear colour");
    }
    mvr::session::RenderRecipe recipe;
    recipe.size = "64x48";
    auto prepared = mvr::session::prepare(recipe);
    if (!prepared) return fail("session::prepare: " + prepared.status().message());
    if (prepared->rig.viewCount() != 2 || prepared->settings.width != 64 ||
        prepared->rig.interaxial != request->rig.interaxial) {
        return fail("session::prepare: not the framed request");
    }
    auto still = mvr::session::renderStill(recipe);
    if (!still) return fail("session::renderStill: " + still.status().message());
    if (still->output.color.size() != 2 || still->output.color[0].rgba != out->color[0].rgba)
        return fail("session::renderStill: not the image of the framed request");
    std::printf("mvr consumer: %s:%s rendered 2 views of 64x48\n", (*backend)->name().c_str(),
                out->method.c_str());
    return 0;
}

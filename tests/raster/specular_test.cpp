// --specular per-view (issue 39 item 1; lighting.h SpecularEye): with the default (Center) every
// view sees the highlight the rig's centre eye sees; with PerView each view sees its own. A
// glossy floor under a directional light has its highlight where the floor mirrors the light
// into the eye: the test finds that point by reflection (no shading code) and projects it with
// each view's matrix, then looks for the highlight in the soft backend's images.
#include <cmath>

#include <gtest/gtest.h>

#include "mvr/core/render.h"
#include "mvr/raster/soft_backend.h"

namespace mvr {
namespace {

constexpr int kW = 160, kH = 120;

/// A 12×12 floor (y = 0, normal +y), dark and glossy: the highlight is sharp and never clips.
Scene floorScene(glm::vec3 towardLight) {
    Scene scene;
    Mesh floor;
    floor.positions = {{-6, 0, -6}, {-6, 0, 6}, {6, 0, 6}, {6, 0, -6}};
    floor.normals.assign(4, glm::vec3(0, 1, 0));
    floor.indices = {0, 1, 2, 0, 2, 3};
    scene.meshes.push_back(std::move(floor));
    Instance inst;
    inst.material = Material(glm::vec3(0.2f), 0.6f, 400.0f);
    scene.instances.push_back(inst);
    Light light;
    light.towardLight = glm::normalize(towardLight);
    scene.lights = {light};
    return scene;
}

Rig threeEyes() {
    Camera cam;
    cam.position = {0.0f, 2.0f, 5.0f};
    cam.target = {0.0f, 0.0f, 0.0f};
    cam.aspect = float(kW) / float(kH);
    RigParams p;
    p.columns = 3, p.interaxial = 1.5f, p.convergence = 5.0f;
    auto rig = makeRig(cam, p);
    EXPECT_TRUE(rig) << rig.status().message();
    return *rig;
}

/// Where the floor y = 0 mirrors the light (toward `l`) into the eye at `eye`: the view vector
/// there is l reflected about +y.
glm::dvec3 mirrorPoint(glm::dvec3 eye, glm::dvec3 l) {
    const glm::dvec3 v(-l.x, l.y, -l.z);
    return eye - (eye.y / v.y) * v;
}

/// A world point's pixel (x right, y down, pixel centres at .5) in `view`.
glm::dvec2 pixelOf(const View& view, glm::dvec3 p) {
    const glm::dvec4 c = glm::dmat4(view.clipFromWorld()) * glm::dvec4(p, 1.0);
    return {(c.x / c.w * 0.5 + 0.5) * kW, (0.5 - c.y / c.w * 0.5) * kH};
}

/// The centroid of the pixels whose red is above half way between the floor's plain colour
/// (the image's median floor red, the darkest lit value) and the brightest.
glm::dvec2 highlightCentre(const Image& img) {
    int lo = 255, hi = 0;
    for (int y = 0; y < img.height; ++y) {
        for (int x = 0; x < img.width; ++x) {
            const Rgba8 c = img.at(x, y);
            if (c.r == 0) continue;  // background
            lo = std::min<int>(lo, c.r), hi = std::max<int>(hi, c.r);
        }
    }
    EXPECT_GT(hi - lo, 60) << "no highlight";
    const int cut = (lo + hi) / 2;
    double sx = 0, sy = 0, n = 0;
    for (int y = 0; y < img.height; ++y) {
        for (int x = 0; x < img.width; ++x) {
            if (img.at(x, y).r <= cut) continue;
            sx += x + 0.5, sy += y + 0.5, n += 1;
        }
    }
    return {sx / n, sy / n};
}

TEST(SpecularEye, HighlightsAreWhereEachEyeSeesTheLightMirrored) {
    const glm::dvec3 l = glm::normalize(glm::dvec3(0.0, 0.5, -1.0));
    const Scene scene = floorScene(glm::vec3(l));
    const Rig rig = threeEyes();
    auto backend = raster::makeSoftBackend();
    RenderSettings s;
    s.width = kW, s.height = kH;
    s.shading = Shading::Pixel;
    for (SpecularEye eye : {SpecularEye::Center, SpecularEye::PerView}) {
        s.specular = eye;
        auto out = backend->render(scene, rig, s, "unified");
        ASSERT_TRUE(out) << out.status().message();
        const glm::dvec3 centrePoint = mirrorPoint(glm::dvec3(rig.centerEye()), l);
        for (int v = 0; v < 3; ++v) {
            const View& view = rig.views[std::size_t(v)];
            const glm::dvec3 p = eye == SpecularEye::PerView
                                     ? mirrorPoint(glm::dvec3(view.eyeWorld), l)
                                     : centrePoint;
            const glm::dvec2 want = pixelOf(view, p);
            const glm::dvec2 got = highlightCentre(out->color[std::size_t(v)]);
            // The spot is stretched along the floor's depth (it is seen at a grazing angle)
            // and its 8-bit plateau is a few pixels wide: its centroid is within 3 pixels.
            EXPECT_NEAR(got.x, want.x, 3.0) << "view " << v << " per-view " << int(eye);
            EXPECT_NEAR(got.y, want.y, 3.0) << "view " << v << " per-view " << int(eye);
        }
    }
    // The outer eyes' own highlights are far from where the centre eye's falls in their
    // images: what the test tells apart is worth telling apart.
    for (int v : {0, 2}) {
        const View& view = rig.views[std::size_t(v)];
        const double apart =
            std::abs(pixelOf(view, mirrorPoint(glm::dvec3(view.eyeWorld), l)).x -
                     pixelOf(view, mirrorPoint(glm::dvec3(rig.centerEye()), l)).x);
        EXPECT_GT(apart, 30.0) << v;
    }
}

// Per-view shading is exact like every soft path: unified == multipass bit for bit (rows, a
// grid, textured and not is covered by the conformance suite), and the centre view of an odd
// row, whose eye is the centre eye, is the Center image exactly.
TEST(SpecularEye, PerViewUnifiedEqualsMultipassAndCentreViewIsCenter) {
    const Scene scene = floorScene(glm::vec3(0.0f, 0.5f, -1.0f));
    const Rig rig = threeEyes();
    auto backend = raster::makeSoftBackend();
    RenderSettings s;
    s.width = kW, s.height = kH;
    s.shading = Shading::Pixel;
    s.specular = SpecularEye::PerView;
    auto un = backend->render(scene, rig, s, "unified");
    auto mp = backend->render(scene, rig, s, "multipass");
    ASSERT_TRUE(un && mp);
    for (int v = 0; v < 3; ++v) {
        EXPECT_EQ(compareImages(un->color[std::size_t(v)], mp->color[std::size_t(v)])
                      .differingPixels,
                  0)
            << v;
    }
    s.specular = SpecularEye::Center;
    auto centre = backend->render(scene, rig, s, "unified");
    ASSERT_TRUE(centre);
    ASSERT_EQ(rig.views[1].eyeWorld, rig.centerEye());
    EXPECT_EQ(compareImages(centre->color[1], un->color[1]).differingPixels, 0);
    EXPECT_GT(compareImages(centre->color[0], un->color[0], 8).differingPixels, 50);
    // Vertex shading asked with per-view is rendered per pixel (shadedSettings).
    s.specular = SpecularEye::PerView;
    s.shading = Shading::Vertex;
    auto promoted = backend->render(scene, rig, s, "unified");
    ASSERT_TRUE(promoted);
    EXPECT_EQ(compareImages(promoted->color[0], un->color[0]).differingPixels, 0);
}

}  // namespace
}  // namespace mvr

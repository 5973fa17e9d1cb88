// The backend registry (mvr/backends.h) and the one validation of a render request
// (mvr::validateRequest): every backend of the build refuses the same bad request with the same
// message and error code.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include <gtest/gtest.h>

#include "mvr/backends.h"
#include "mvr/raster/soft_backend.h"
#include "mvr_test_support.h"

namespace mvr {
namespace {

Scene oneTriangle() {
    Mesh m;
    m.positions = {{-0.5f, -0.5f, 0.0f}, {0.5f, -0.5f, 0.0f}, {0.0f, 0.5f, 0.0f}};
    m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    m.indices = {0, 1, 2};
    Scene s;
    s.meshes.push_back(m);
    s.instances.push_back({});
    s.lights = defaultLights();
    return s;
}

Rig stereoRig() {
    Camera c;
    c.position = {0, 0, 3};
    return std::move(makeRig(c, RigParams{.columns = 2, .convergence = 3.0f})).value();
}

RenderSettings small() { return RenderSettings{.width = 32, .height = 24}; }

TEST(Registry, ListsTheBuiltInBackendsSoftFirst) {
    const auto names = backendNames();
    ASSERT_FALSE(names.empty());
    EXPECT_EQ(names.front(), "soft");
    for (const BackendEntry& e : backends()) {
        auto b = makeBackend(e.name);
        ASSERT_TRUE(b) << e.name << ": " << b.status().message();
        EXPECT_EQ((*b)->name(), e.name);
        EXPECT_FALSE(e.description.empty());
        const auto methods = (*b)->methods();
        EXPECT_NE(std::find(methods.begin(), methods.end(), (*b)->defaultMethod()), methods.end())
            << e.name << "'s default method is not one of its methods";
    }
}

TEST(Registry, UnknownBackendIsAUsageErrorListingTheKnownOnes) {
    auto b = makeBackend("vulkan-rt");
    ASSERT_FALSE(b);
    EXPECT_EQ(b.status().code(), ErrorCode::Usage);
    EXPECT_NE(b.status().message().find("vulkan-rt"), std::string::npos);
    for (const std::string& n : backendNames()) {
        EXPECT_NE(b.status().message().find(n), std::string::npos) << b.status().message();
    }
}

TEST(Registry, BackendOptionsAreChecked) {
    auto bad = makeBackend("soft", BackendOptions{.threads = 0, .simd = "neon9"});
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.status().code(), ErrorCode::Usage);
    EXPECT_NE(bad.status().message().find("neon9"), std::string::npos);
    EXPECT_FALSE(makeBackend("soft", BackendOptions{.threads = -2}));
    EXPECT_TRUE(makeBackend("soft", BackendOptions{.threads = 1, .simd = "scalar"}));
}

TEST(Registry, ParsesBackendMethodSpecs) {
    auto full = parseMethodSpec("soft:multipass");
    ASSERT_TRUE(full) << full.status().message();
    EXPECT_EQ(full->backend, "soft");
    EXPECT_EQ(full->method, "multipass");
    EXPECT_EQ(full->text(), "soft:multipass");
    auto bare = parseMethodSpec("soft");
    ASSERT_TRUE(bare);
    EXPECT_EQ(bare->method, "unified");  // soft's default: its fastest exact method
    for (const char* bad : {"soft:", "soft:bogus", ":unified", "nope:unified", ""}) {
        auto r = parseMethodSpec(bad);
        ASSERT_FALSE(r) << bad;
        EXPECT_EQ(r.status().code(), ErrorCode::Usage) << bad;
        EXPECT_NE(r.status().message().find(std::string("'") + bad + "'"), std::string::npos)
            << r.status().message();
    }
}

TEST(Registry, ABackendJoinsByRegistering) {
    // A real backend under another name (the soft rasterizer pinned to the scalar path).
    BackendEntry scalar;
    scalar.name = "soft-scalar-test";
    scalar.description = "the soft backend on its scalar path";
    scalar.make = [](const BackendOptions&) -> Result<std::unique_ptr<Backend>> {
        return raster::makeSoftBackend({.threads = 1, .simd = raster::SimdPath::Scalar});
    };
    Status s = registerBackend(scalar);
    ASSERT_TRUE(s) << s.message();
    const auto names = backendNames();
    EXPECT_EQ(names.back(), "soft-scalar-test");
    auto spec = parseMethodSpec("soft-scalar-test:multipass");
    EXPECT_TRUE(spec) << spec.status().message();
    // Taken, empty and ':' names, and a row without a factory, are refused.
    auto entry = [](const char* name, bool withFactory = true) {
        BackendEntry e;
        e.name = name;
        if (withFactory) e.make = backends()[0].make;
        return e;
    };
    EXPECT_EQ(registerBackend(entry("soft")).code(), ErrorCode::Usage);
    EXPECT_FALSE(registerBackend(entry("")));
    EXPECT_FALSE(registerBackend(entry("a:b")));
    EXPECT_FALSE(registerBackend(entry("no-factory", false)));
}

TEST(Registry, ComposeForGivesTheCpuImageForTheSoftBackend) {
    auto soft = makeBackend("soft");
    ASSERT_TRUE(soft);
    Image left(4, 2), right(4, 2);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x) {
            left.set(x, y, {std::uint8_t(40 * x), 10, 200, 255});
            right.set(x, y, {5, std::uint8_t(60 * y), 90, 255});
        }
    const std::vector<Image> views{left, right};
    auto a = composeFor(**soft, "sbs", views, {});
    auto b = composite::compose("sbs", views, {});
    ASSERT_TRUE(a && b);
    EXPECT_EQ(*a, *b);
    EXPECT_FALSE(composeFor(**soft, "no-such-format", views, {}));
}

// ---- one validation ---------------------------------------------------------------------------

struct BadRequest {
    const char* what;
    Scene scene;
    Rig rig;
    RenderSettings settings;
};

std::vector<BadRequest> badRequests() {
    std::vector<BadRequest> out;
    {
        BadRequest r{"NaN view matrix", oneTriangle(), stereoRig(), small()};
        r.rig.views[1].clipFromView[0][0] = std::numeric_limits<float>::quiet_NaN();
        out.push_back(r);
    }
    {
        BadRequest r{"no views", oneTriangle(), stereoRig(), small()};
        r.rig.views.clear();
        out.push_back(r);
    }
    out.push_back({"empty scene", Scene{}, stereoRig(), small()});
    {
        BadRequest r{"infinite instance transform", oneTriangle(), stereoRig(), small()};
        r.scene.instances[0].worldFromModel[3][0] = std::numeric_limits<float>::infinity();
        out.push_back(r);
    }
    out.push_back(
        {"zero size", oneTriangle(), stereoRig(), RenderSettings{.width = 0, .height = 24}});
    {
        // kMaxViews + 1 views: more than kMaxViews.
        BadRequest r{"too many views", oneTriangle(), stereoRig(), small()};
        while (r.rig.viewCount() <= kMaxViews) r.rig.views.push_back(r.rig.views[0]);
        out.push_back(r);
    }
    {
        // 16384 x 16384 x 5 views x 8 bytes = 10 GiB > kMaxFramebufferBytes.
        BadRequest r{"over the memory budget", oneTriangle(), stereoRig(),
                     RenderSettings{.width = 16384, .height = 16384}};
        while (r.rig.viewCount() < 5) r.rig.views.push_back(r.rig.views[0]);
        out.push_back(r);
    }
    {
        BadRequest r{"five lights", oneTriangle(), stereoRig(), small()};
        r.scene.lights.resize(kMaxLights + 1);
        out.push_back(r);
    }
    return out;
}

TEST(Validation, EveryBackendRefusesABadRequestWithTheSameMessageAndCode) {
    for (const BadRequest& r : badRequests()) {
        const Status expected = validateRequest(r.scene, r.rig, r.settings);
        ASSERT_FALSE(expected) << r.what << " passed validation";
        for (const BackendEntry& e : backends()) {
            auto backend = makeBackend(e.name);
            ASSERT_TRUE(backend);
            auto out = (*backend)->render(r.scene, r.rig, r.settings, (*backend)->defaultMethod());
            ASSERT_FALSE(out) << e.name << " rendered: " << r.what;
            EXPECT_EQ(out.status().code(), expected.code()) << e.name << ": " << r.what;
            EXPECT_EQ(out.status().message(), expected.message()) << e.name << ": " << r.what;
        }
    }
}

// The same without any EGL driver (glvnd pointed at nothing): a GPU backend that cannot make a
// context still gives validateRequest's message for a bad request, not "no EGL display".
TEST(Validation, TheSameMessageWithoutADisplay) {
    if (std::getenv("MVR_BACKENDS_TEST_NO_EGL")) MVR_SKIP(NotApplicable) << "the child run";
    char exe[4096] = {};
    const ssize_t n = readlink("/proc/self/exe", exe, sizeof(exe) - 1);
    ASSERT_GT(n, 0);
    const std::string cmd =
        "MVR_BACKENDS_TEST_NO_EGL=1 __EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json '" +
        std::string(exe, std::size_t(n)) +
        "' --gtest_filter=Validation.EveryBackendRefusesABadRequestWithTheSameMessageAndCode"
        " > /dev/null 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0);
}

TEST(Validation, MessagesNameTheCulprit) {
    auto reqs = badRequests();
    EXPECT_NE(
        validateRequest(reqs[0].scene, reqs[0].rig, reqs[0].settings).message().find("view 1"),
        std::string::npos);
    const Status budget = validateRequest(reqs[6].scene, reqs[6].rig, reqs[6].settings);
    EXPECT_EQ(budget.code(), ErrorCode::Unsupported);
    EXPECT_NE(budget.message().find("GiB"), std::string::npos) << budget.message();
    EXPECT_NE(budget.message().find("16384x16384"), std::string::npos) << budget.message();
    const Status inst = validateRequest(reqs[3].scene, reqs[3].rig, reqs[3].settings);
    EXPECT_NE(inst.message().find("instance 0"), std::string::npos) << inst.message();
    EXPECT_TRUE(validateRequest(oneTriangle(), stereoRig(), small()));
}

}  // namespace
}  // namespace mvr

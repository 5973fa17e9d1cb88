// The "auto" backend (mvr/backends.h kAutoBackend): a choice of the registry, not a row; one
// method, "auto"; it picks one of the candidates (each registered backend's default method,
// gl: the exact method gl's auto measured fastest), renders exactly that backend:method's
// images, says so in the note with every candidate's time, and keeps the choice for later
// frames of the same kind of request. Nothing here checks which one is faster.
#include <algorithm>
#include <atomic>
#include <cstring>
#include <regex>

#include <gtest/gtest.h>

#include "mvr/backends.h"
#include "mvr/raster/soft_backend.h"

namespace mvr {
namespace {

Scene twoTriangles() {
    Mesh m;
    m.positions = {{-0.6f, -0.5f, 0.0f},  {0.5f, -0.5f, 0.0f}, {0.0f, 0.6f, 0.0f},
                   {-0.3f, -0.2f, -0.5f}, {0.8f, 0.0f, -0.5f}, {0.2f, 0.7f, -0.5f}};
    m.normals = {{0, 0, 1},       {0, 0, 1},       {0, 0, 1},
                 {0, 0.6f, 0.8f}, {0, 0.6f, 0.8f}, {0, 0.6f, 0.8f}};
    m.indices = {0, 1, 2, 3, 4, 5};
    Scene s;
    s.meshes.push_back(m);
    s.instances.push_back({});
    s.lights = defaultLights();
    return s;
}

Rig stereoRig(float x = 0.0f) {
    Camera c;
    c.position = {x, 0, 3};
    return std::move(makeRig(c, RigParams{.columns = 2, .convergence = 3.0f})).value();
}

RenderSettings settings(int w = 48, int h = 32) {
    return RenderSettings{.width = w, .height = h, .shading = Shading::Pixel};
}

std::unique_ptr<Backend> makeAuto() {
    auto b = makeBackend(kAutoBackend);
    EXPECT_TRUE(b) << b.status().message();
    return b ? std::move(b).value() : nullptr;
}

TEST(AutoBackend, IsAChoiceOfTheRegistryNotARow) {
    const auto names = backendNames();
    EXPECT_EQ(std::count(names.begin(), names.end(), "auto"), 0);
    for (const BackendEntry& e : backends()) EXPECT_NE(e.name, "auto");
    EXPECT_EQ(backendChoices().back(), "auto");
    auto entry = findBackend("auto");
    ASSERT_TRUE(entry) << entry.status().message();
    EXPECT_FALSE((*entry)->description.empty());
    const bool anyGpu = std::any_of(backends().begin(), backends().end(),
                                    [](const BackendEntry& e) { return e.gpu; });
    EXPECT_EQ((*entry)->gpu, anyGpu);
    auto unknown = makeBackend("vulkan-rt");
    ASSERT_FALSE(unknown);
    EXPECT_NE(unknown.status().message().find("auto"), std::string::npos);
    BackendEntry taken;
    taken.name = "auto";
    taken.make = backends()[0].make;
    EXPECT_EQ(registerBackend(taken).code(), ErrorCode::Usage);
    // Options are checked as soft's are.
    EXPECT_EQ(makeBackend("auto", {.threads = 0, .simd = "neon9"}).status().code(),
              ErrorCode::Usage);
    EXPECT_FALSE(makeBackend("auto", {.threads = -1}));
}

// One method, "auto"; every other (any backend's method) is a Usage error that says how to pick
// a method instead, from supports() and from render().
TEST(AutoBackend, HasOneMethodAuto) {
    auto a = makeAuto();
    ASSERT_TRUE(a);
    EXPECT_EQ(a->name(), "auto");
    EXPECT_EQ(a->methods(), std::vector<std::string>{"auto"});
    EXPECT_EQ(a->defaultMethod(), "auto");
    EXPECT_TRUE(a->supports("auto"));
    EXPECT_FALSE(a->lastStats());
    for (const std::string& name : backendNames()) {
        auto b = makeBackend(name);
        ASSERT_TRUE(b);
        for (const std::string& m : (*b)->methods()) {
            if (m == "auto") continue;
            const Status s = a->supports(m);
            EXPECT_EQ(s.code(), ErrorCode::Usage) << m;
            EXPECT_NE(s.message().find("--backend"), std::string::npos) << s.message();
            auto r = a->render(twoTriangles(), stereoRig(), settings(), m);
            ASSERT_FALSE(r) << m;
            EXPECT_EQ(r.status().message(), s.message());
        }
    }
    auto spec = parseMethodSpec("auto");
    ASSERT_TRUE(spec) << spec.status().message();
    EXPECT_EQ(spec->text(), "auto:auto");
    auto bad = parseMethodSpec("auto:unified");
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.status().code(), ErrorCode::Usage);
    // A bad request gets the message every backend gives.
    const Status expected = validateRequest(twoTriangles(), stereoRig(), settings(0, 32));
    auto invalid = a->render(twoTriangles(), stereoRig(), settings(0, 32), "auto");
    ASSERT_FALSE(invalid);
    EXPECT_EQ(invalid.status().message(), expected.message());
}

/// The candidates that can run here: "backend:default method" (gl's "auto" stands for the
/// method it picks).
std::vector<std::string> runnableCandidates() {
    std::vector<std::string> out;
    for (const BackendEntry& e : backends()) {
        auto b = e.make({});
        if (!b || !(*b)->supports((*b)->defaultMethod())) continue;
        out.push_back(e.name + ":" + (*b)->defaultMethod());
    }
    return out;
}

void expectSameImages(const RenderOutput& a, const RenderOutput& b, const std::string& what) {
    ASSERT_EQ(a.color.size(), b.color.size()) << what;
    for (std::size_t v = 0; v < a.color.size(); ++v)
        EXPECT_TRUE(a.color[v] == b.color[v]) << what << ": view " << v;
    ASSERT_EQ(a.depth.size(), b.depth.size()) << what;
    for (std::size_t v = 0; v < a.depth.size(); ++v) {
        ASSERT_EQ(a.depth[v].depth.size(), b.depth[v].depth.size()) << what;
        EXPECT_EQ(std::memcmp(a.depth[v].depth.data(), b.depth[v].depth.data(),
                              a.depth[v].depth.size() * sizeof(float)),
                  0)
            << what << ": depth of view " << v;
    }
}

// The pick is one of the candidates; the images are exactly that backend:method's; the note
// names the pick and every candidate's measured time; lastStats() is the pick's frame.
TEST(AutoBackend, PicksACandidateAndRendersItsImages) {
    const std::vector<std::string> candidates = runnableCandidates();
    ASSERT_FALSE(candidates.empty());
    auto a = makeAuto();
    ASSERT_TRUE(a);
    const Scene scene = twoTriangles();
    auto out = a->render(scene, stereoRig(), settings(), "auto");
    ASSERT_TRUE(out) << out.status().message();
    const std::string picked = out->method;
    const std::size_t colon = picked.find(':');
    ASSERT_NE(colon, std::string::npos) << picked;
    const std::string backend = picked.substr(0, colon), method = picked.substr(colon + 1);
    EXPECT_NE(method, "auto");
    bool isCandidate = false;
    for (const std::string& c : candidates) {
        // soft:unified as such; gl:auto stands for any exact gl method its auto may pick.
        isCandidate = isCandidate || c == picked || c == backend + ":auto";
    }
    EXPECT_TRUE(isCandidate) << picked;
    EXPECT_EQ(out->note.rfind("auto picked " + picked + ": ", 0), 0u) << out->note;
    for (const std::string& c : candidates) {
        const std::string name = c.substr(0, c.find(':'));
        const std::regex time(name + ":[a-z0-9-]+ [0-9]+\\.[0-9]{2} ms");
        EXPECT_TRUE(std::regex_search(out->note, time)) << c << " in: " << out->note;
    }
    ASSERT_TRUE(a->lastStats());
    EXPECT_EQ(a->lastStats()->method, picked);

    auto direct = makeBackend(backend);
    ASSERT_TRUE(direct);
    auto ref = (*direct)->render(scene, stereoRig(), settings(), method);
    ASSERT_TRUE(ref) << ref.status().message();
    expectSameImages(*out, *ref, picked);

    // A later frame of the same kind (another camera): the same pick, its images.
    auto again = a->render(scene, stereoRig(0.4f), settings(), "auto");
    ASSERT_TRUE(again);
    EXPECT_EQ(again->method, picked);
    EXPECT_EQ(again->note, out->note);
    auto ref2 = (*direct)->render(scene, stereoRig(0.4f), settings(), method);
    ASSERT_TRUE(ref2);
    expectSameImages(*again, *ref2, picked + " (second frame)");
}

// The choice is measured once per kind of request: a backend registered here (soft, counting
// its renders) is a candidate like the others; it renders 3 times for the first frame (one
// warm-up, the best of two), then once per frame if it was picked, never if not; another size
// is measured again.
std::atomic<int> gRenders{0};

class CountingBackend final : public Backend {
public:
    CountingBackend() : mSoft(raster::makeSoftBackend({.threads = 1})) {}
    std::string name() const override { return "counting-test"; }
    std::vector<std::string> methods() const override { return mSoft->methods(); }
    std::string defaultMethod() const override { return mSoft->defaultMethod(); }
    Status supports(const std::string& m) const override { return mSoft->supports(m); }
    Result<RenderOutput> render(const Scene& scene, const Rig& rig, const RenderSettings& s,
                                const std::string& m) override {
        ++gRenders;
        return mSoft->render(scene, rig, s, m);
    }
    std::optional<RenderStats> lastStats() const override { return mSoft->lastStats(); }

private:
    std::unique_ptr<Backend> mSoft;
};

TEST(AutoBackend, KeepsItsChoiceForLaterFramesOfTheSameKind) {
    BackendEntry e;
    e.name = "counting-test";
    e.description = "soft, counting its renders";
    e.make = [](const BackendOptions&) -> Result<std::unique_ptr<Backend>> {
        return std::unique_ptr<Backend>(std::make_unique<CountingBackend>());
    };
    ASSERT_TRUE(registerBackend(e));
    auto a = makeAuto();
    ASSERT_TRUE(a);
    const Scene scene = twoTriangles();
    auto first = a->render(scene, stereoRig(), settings(), "auto");
    ASSERT_TRUE(first) << first.status().message();
    EXPECT_NE(first->note.find("counting-test:unified "), std::string::npos) << first->note;
    EXPECT_EQ(gRenders.load(), 3);
    const bool picked = first->method == "counting-test:unified";
    for (int frame = 1; frame <= 3; ++frame) {
        auto next = a->render(scene, stereoRig(0.1f * float(frame)), settings(), "auto");
        ASSERT_TRUE(next);
        EXPECT_EQ(next->method, first->method);
        EXPECT_EQ(gRenders.load(), 3 + (picked ? frame : 0));
    }
    const int before = gRenders.load();
    auto other = a->render(scene, stereoRig(), settings(64, 40), "auto");
    ASSERT_TRUE(other);
    EXPECT_NE(other->note.find("at 64x40"), std::string::npos) << other->note;
    EXPECT_EQ(gRenders.load(), before + 3);
}

}  // namespace
}  // namespace mvr

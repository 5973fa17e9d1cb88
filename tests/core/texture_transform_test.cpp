// glTF KHR_texture_transform and texture coordinate sets 0 and 1 (issue 39 item 4): the texture
// coordinates loadScene() gives a mesh equal the extension's formula, written out here as
// matrices (uv' = T · R · S · uv, R's rows (cos r, sin r), (−sin r, cos r)), for offset, scale
// and rotation alone and together; the README's example lands where its text says; the set
// comes from texCoord (the extension's wins); a missing set warns (an error with strict); bad
// values are refused with the file and the material named.
#include <cmath>
#include <numbers>

#include <fmt/core.h>
#include <gtest/gtest.h>

#include "mvr/io/scene_io.h"
#include "texture_transform_fixture.h"

namespace mvr {
namespace {

using test::QuadVertex;
using test::TransformQuadOptions;

/// KHR_texture_transform's matrix product, in doubles, as the extension defines it.
glm::dvec2 specTransform(glm::dvec2 uv, glm::dvec2 offset, double rotation, glm::dvec2 scale) {
    const double c = std::cos(rotation), s = std::sin(rotation);
    // Row-major 3×3 matrices.
    const double T[3][3] = {{1, 0, offset.x}, {0, 1, offset.y}, {0, 0, 1}};
    const double R[3][3] = {{c, s, 0}, {-s, c, 0}, {0, 0, 1}};
    const double S[3][3] = {{scale.x, 0, 0}, {0, scale.y, 0}, {0, 0, 1}};
    auto mul = [](const double(&a)[3][3], const double(&b)[3][3], double(&out)[3][3]) {
        for (int r = 0; r < 3; ++r)
            for (int k = 0; k < 3; ++k) {
                out[r][k] = 0;
                for (int m = 0; m < 3; ++m) out[r][k] += a[r][m] * b[m][k];
            }
    };
    double TR[3][3], M[3][3];
    mul(T, R, TR);
    mul(TR, S, M);
    return {M[0][0] * uv.x + M[0][1] * uv.y + M[0][2], M[1][0] * uv.x + M[1][1] * uv.y + M[1][2]};
}

std::string transformJson(glm::dvec2 offset, double rotation, glm::dvec2 scale) {
    return fmt::format(
        R"(,"extensions":{{"KHR_texture_transform":{{"offset":[{},{}],"rotation":{},)"
        R"("scale":[{},{}]}}}})",
        offset.x, offset.y, rotation, scale.x, scale.y);
}

Result<Scene> load(const test::TempDir& dir, const std::string& name, const TransformQuadOptions& o,
                   SceneLoadInfo* info = nullptr) {
    return loadScene(test::writeTransformQuad(dir.path(), name, o), info);
}

/// The fixture's vertex at `position` (the loader reorders vertices).
const QuadVertex& vertexAt(const glm::vec3& position) {
    static const std::vector<QuadVertex> verts = test::transformQuadVertices();
    for (const QuadVertex& v : verts)
        if (glm::length(v.position - position) < 1e-6f) return v;
    ADD_FAILURE() << "no fixture vertex at " << position.x << "," << position.y;
    return verts[0];
}

/// Every loaded vertex's texcoord equals `expected(its fixture vertex)`.
template <class F>
void expectTexcoords(const Scene& scene, F expected, const std::string& what) {
    ASSERT_EQ(scene.meshes.size(), 1u) << what;
    const Mesh& mesh = scene.meshes[0];
    ASSERT_EQ(mesh.positions.size(), 9u) << what;
    ASSERT_EQ(mesh.texcoords.size(), 9u) << what;
    for (std::size_t k = 0; k < mesh.positions.size(); ++k) {
        const glm::dvec2 want = expected(vertexAt(mesh.positions[k]));
        EXPECT_NEAR(mesh.texcoords[k].x, want.x, 1e-5) << what << " vertex " << k;
        EXPECT_NEAR(mesh.texcoords[k].y, want.y, 1e-5) << what << " vertex " << k;
    }
}

TEST(TextureTransform, ApplyPlacesTheReadmeExampleInTheLowerLeftQuadrantRotated) {
    // The extension's README: offset (0, 1), rotation π/2, scale 0.5 "utilizes only the lower
    // left quadrant of the source image, rotated clockwise 90°" (uv (0, 0) top-left, v down).
    TextureTransform t;
    t.offset = {0.0f, 1.0f};
    t.rotation = std::numbers::pi_v<float> / 2.0f;
    t.scale = {0.5f, 0.5f};
    const std::pair<glm::vec2, glm::vec2> corners[] = {{{0, 0}, {0.0f, 1.0f}},
                                                       {{1, 0}, {0.0f, 0.5f}},
                                                       {{0, 1}, {0.5f, 1.0f}},
                                                       {{1, 1}, {0.5f, 0.5f}}};
    for (const auto& [uv, want] : corners) {
        const glm::vec2 got = t.apply(uv);
        EXPECT_NEAR(got.x, want.x, 1e-6f) << uv.x << "," << uv.y;
        EXPECT_NEAR(got.y, want.y, 1e-6f) << uv.x << "," << uv.y;
    }
}

TEST(TextureTransform, LoadedTexcoordsFollowTheSpecFormula) {
    test::TempDir dir("mvr-texture-transform");
    struct Case {
        const char* what;
        glm::dvec2 offset;
        double rotation;
        glm::dvec2 scale;
    };
    const Case cases[] = {
        {"offset", {0.5, -0.25}, 0.0, {1, 1}},
        {"scale", {0, 0}, 0.0, {2.0, -0.5}},
        {"rotation", {0, 0}, 0.3, {1, 1}},
        {"rotation 90", {0, 0}, std::numbers::pi / 2, {1, 1}},
        {"together", {0.25, 0.75}, -1.1, {3.0, 0.5}},
    };
    for (const Case& c : cases) {
        TransformQuadOptions o;
        o.baseColorTextureExtra = transformJson(c.offset, c.rotation, c.scale);
        SceneLoadInfo info;
        auto scene = load(dir, "quad", o, &info);
        ASSERT_TRUE(scene) << c.what << ": " << scene.status().message();
        EXPECT_TRUE(info.warnings.empty()) << c.what << ": " << info.warnings[0];
        expectTexcoords(
            *scene,
            [&](const QuadVertex& v) {
                return specTransform(glm::dvec2(v.uv0), c.offset, c.rotation, c.scale);
            },
            c.what);
        // The transform is recorded on the material as the file states it.
        ASSERT_EQ(scene->instances.size(), 1u);
        const Material& m = scene->instances[0].material;
        EXPECT_EQ(m.baseColorTexture, 0);
        EXPECT_EQ(m.baseColorTexCoord, 0);
        ASSERT_TRUE(m.baseColorTransform) << c.what;
        EXPECT_FLOAT_EQ(m.baseColorTransform->offset.x, float(c.offset.x));
        EXPECT_FLOAT_EQ(m.baseColorTransform->offset.y, float(c.offset.y));
        EXPECT_FLOAT_EQ(m.baseColorTransform->rotation, float(c.rotation));
        EXPECT_FLOAT_EQ(m.baseColorTransform->scale.x, float(c.scale.x));
        EXPECT_FLOAT_EQ(m.baseColorTransform->scale.y, float(c.scale.y));
        EXPECT_FALSE(m.baseColorTransform->texCoord);
    }
}

TEST(TextureTransform, WithoutTheExtensionTexcoordsAreTheFilesAndNothingIsRecorded) {
    test::TempDir dir("mvr-texture-transform");
    auto scene = load(dir, "plain", {});
    ASSERT_TRUE(scene) << scene.status().message();
    expectTexcoords(
        *scene, [](const QuadVertex& v) { return glm::dvec2(v.uv0); }, "plain");
    const Material& m = scene->instances[0].material;
    EXPECT_FALSE(m.baseColorTransform);
    EXPECT_FALSE(m.normalTransform);
}

TEST(TextureTransform, DefaultsOfAnEmptyExtensionObjectAreTheIdentity) {
    test::TempDir dir("mvr-texture-transform");
    TransformQuadOptions o;
    o.baseColorTextureExtra = R"(,"extensions":{"KHR_texture_transform":{}})";
    auto scene = load(dir, "empty", o);
    ASSERT_TRUE(scene) << scene.status().message();
    expectTexcoords(
        *scene, [](const QuadVertex& v) { return glm::dvec2(v.uv0); }, "empty");
    ASSERT_TRUE(scene->instances[0].material.baseColorTransform);
}

TEST(TextureTransform, TexCoordChoosesTheSetAndTheExtensionsOverrideWins) {
    test::TempDir dir("mvr-texture-transform");
    const glm::dvec2 offset(0.125, 0.5), scale(2, 3);
    const double rotation = 0.7;
    const std::string tx = fmt::format(R"("offset":[{},{}],"rotation":{},"scale":[{},{}])",
                                       offset.x, offset.y, rotation, scale.x, scale.y);
    struct Case {
        std::string extra;
        int set;  // the set the base colour must read
    };
    const Case cases[] = {
        {R"(,"texCoord":1)", 1},
        {fmt::format(R"(,"texCoord":1,"extensions":{{"KHR_texture_transform":{{{}}}}})", tx), 1},
        {fmt::format(R"(,"extensions":{{"KHR_texture_transform":{{{},"texCoord":1}}}})", tx), 1},
        {fmt::format(
             R"(,"texCoord":1,"extensions":{{"KHR_texture_transform":{{{},"texCoord":0}}}})", tx),
         0},
    };
    for (const Case& c : cases) {
        TransformQuadOptions o;
        o.baseColorTextureExtra = c.extra;
        SceneLoadInfo info;
        auto scene = load(dir, "sets", o, &info);
        ASSERT_TRUE(scene) << c.extra << ": " << scene.status().message();
        EXPECT_TRUE(info.warnings.empty()) << c.extra;
        const bool transformed = c.extra.find("KHR_texture_transform") != std::string::npos;
        expectTexcoords(
            *scene,
            [&](const QuadVertex& v) {
                const glm::dvec2 uv(c.set == 1 ? v.uv1 : v.uv0);
                return transformed ? specTransform(uv, offset, rotation, scale) : uv;
            },
            c.extra);
        EXPECT_EQ(scene->instances[0].material.baseColorTexCoord, c.set) << c.extra;
    }
}

TEST(TextureTransform, AMissingSetWarnsAndFallsBackToSetZeroStrictRefuses) {
    test::TempDir dir("mvr-texture-transform");
    TransformQuadOptions o;
    o.texcoord1 = false;
    o.baseColorTextureExtra =
        R"(,"texCoord":1,"extensions":{"KHR_texture_transform":{"offset":[0.5,0]}})";
    const auto path = test::writeTransformQuad(dir.path(), "noset", o);
    const std::string line = fmt::format(
        "mvr::loadScene(): {}: material 'Checker': its base colour texture reads texture "
        "coordinate set 1 (TEXCOORD_1), which mesh 'Plane' does not have",
        path.string());
    SceneLoadInfo info;
    auto scene = loadScene(path, &info);
    ASSERT_TRUE(scene) << scene.status().message();
    ASSERT_EQ(info.warnings.size(), 1u);
    EXPECT_EQ(info.warnings[0], line + ": set 0 is used (--strict: an error)");
    // Set 0, with the transform.
    expectTexcoords(
        *scene, [](const QuadVertex& v) { return glm::dvec2(v.uv0) + glm::dvec2(0.5, 0.0); },
        "fallback");
    SceneLoadInfo strict;
    strict.strict = true;
    auto refused = loadScene(path, &strict);
    ASSERT_FALSE(refused);
    EXPECT_EQ(refused.status().code(), ErrorCode::Input);
    EXPECT_EQ(refused.status().message(), line);
}

TEST(TextureTransform, OtherSlotsAreRecordedAndLeaveTheBaseColourCoordinates) {
    test::TempDir dir("mvr-texture-transform");
    TransformQuadOptions o;
    o.baseColorTextureExtra = R"(,"extensions":{"KHR_texture_transform":{"offset":[0.5,0]}})";
    o.materialExtra =
        R"(,"normalTexture":{"index":0,"scale":1,"extensions":{"KHR_texture_transform":)"
        R"({"rotation":1.5,"texCoord":1}}},)"
        R"("occlusionTexture":{"index":0,"extensions":{"KHR_texture_transform":)"
        R"({"scale":[2,2]}}},)"
        R"("emissiveTexture":{"index":0,"extensions":{"KHR_texture_transform":)"
        R"({"offset":[0,0.25]}}},"emissiveFactor":[1,1,1])";
    auto scene = load(dir, "slots", o);
    ASSERT_TRUE(scene) << scene.status().message();
    expectTexcoords(
        *scene, [](const QuadVertex& v) { return glm::dvec2(v.uv0) + glm::dvec2(0.5, 0.0); },
        "slots");
    const Material& m = scene->instances[0].material;
    ASSERT_TRUE(m.normalTransform);
    EXPECT_FLOAT_EQ(m.normalTransform->rotation, 1.5f);
    EXPECT_EQ(m.normalTransform->texCoord, 1);
    ASSERT_TRUE(m.occlusionTransform);
    EXPECT_EQ(m.occlusionTransform->scale, glm::vec2(2.0f));
    ASSERT_TRUE(m.emissiveTransform);
    EXPECT_EQ(m.emissiveTransform->offset, glm::vec2(0.0f, 0.25f));
    EXPECT_FALSE(m.metallicRoughnessTransform);
}

TEST(TextureTransform, BadValuesAreRefusedNamingTheFileAndTheMaterial) {
    test::TempDir dir("mvr-texture-transform");
    const std::string bct = "pbrMetallicRoughness.baseColorTexture";
    const std::string ext = bct + ".extensions.KHR_texture_transform";
    struct Case {
        std::string baseColorExtra, materialExtra, materialName;
        std::string where, why;
    };
    const Case cases[] = {
        {R"(,"extensions":{"KHR_texture_transform":{"offset":[1e39,0]}})", "", "Checker",
         ext + ".offset", "expected 2 finite numbers, got [1e+39,0]"},
        {R"(,"extensions":{"KHR_texture_transform":{"scale":[2]}})", "", "Checker", ext + ".scale",
         "expected 2 finite numbers, got [2]"},
        {R"(,"extensions":{"KHR_texture_transform":{"rotation":-1e300}})", "", "Checker",
         ext + ".rotation", "expected a finite number (radians), got -1e+300"},
        {R"(,"extensions":{"KHR_texture_transform":{"rotation":"90"}})", "", "Checker",
         ext + ".rotation", "expected a finite number (radians), got \"90\""},
        {R"(,"extensions":{"KHR_texture_transform":[0.5,0]})", "", "Checker", ext,
         "expected an object, got [0.5,0]"},
        {R"(,"texCoord":2)", "", "Checker", bct + ".texCoord",
         "2 is not a texture coordinate set mvr reads (0 or 1)"},
        {R"(,"extensions":{"KHR_texture_transform":{"texCoord":3}})", "", "Checker",
         ext + ".texCoord", "3 is not a texture coordinate set mvr reads (0 or 1)"},
        {"",
         R"(,"normalTexture":{"index":0,"extensions":{"KHR_texture_transform":)"
         R"({"offset":[0,1e39]}}})",
         "Bump", "normalTexture.extensions.KHR_texture_transform.offset",
         "expected 2 finite numbers, got [0,1e+39]"},
    };
    for (const Case& c : cases) {
        TransformQuadOptions o;
        o.baseColorTextureExtra = c.baseColorExtra;
        o.materialExtra = c.materialExtra;
        o.materialName = c.materialName;
        const auto path = test::writeTransformQuad(dir.path(), "bad", o);
        auto scene = loadScene(path);
        ASSERT_FALSE(scene) << c.where;
        EXPECT_EQ(scene.status().code(), ErrorCode::Input);
        EXPECT_EQ(scene.status().message(),
                  fmt::format("mvr::loadScene(): {}: material '{}' (materials[0]): {}: {}",
                              path.string(), c.materialName, c.where, c.why));
    }
}

}  // namespace
}  // namespace mvr

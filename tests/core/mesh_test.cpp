// Mesh loading: the shared models, every format on tiny files, and bad input of every kind.
#include "mvr/core/mesh.h"
#include "mvr/io/mesh_io.h"

#include <cstdlib>
#include <fstream>
#include <string>

#include <fmt/core.h>
#include <gtest/gtest.h>

#include "test_files.h"
#include "mvr_test_support.h"

namespace mvr {
namespace {

std::filesystem::path sharedModels() {
    return ::mvr::test::modelsDir();
}

using test::TempDir;

const char* kCubeObj = R"(# a unit cube, quads, no normals
v -1 -1 -1
v 1 -1 -1
v 1 1 -1
v -1 1 -1
v -1 -1 1
v 1 -1 1
v 1 1 1
v -1 1 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8
)";

const char* kTetraPly = R"(ply
format ascii 1.0
comment a tetrahedron
element vertex 4
property float x
property float y
property float z
element face 4
property list uchar int vertex_indices
end_header
0 0 0
1 0 0
0 1 0
0 0 1
3 0 2 1
3 0 1 3
3 0 3 2
3 1 2 3
)";

using test::base64;

/// A glTF 2.0 file with one indexed triangle in an embedded buffer, placed by a node translation.
std::string triangleGltf() {
    const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const std::uint16_t indices[3] = {0, 1, 2};
    std::string buffer(reinterpret_cast<const char*>(positions), sizeof positions);
    buffer.append(reinterpret_cast<const char*>(indices), sizeof indices);
    buffer.append(2, '\0');  // pad to 4 bytes
    return fmt::format(R"({{
  "asset": {{"version": "2.0"}},
  "scene": 0,
  "scenes": [{{"nodes": [0]}}],
  "nodes": [{{"mesh": 0, "translation": [10, 0, 0]}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1}}]}}],
  "buffers": [{{"byteLength": {}, "uri": "data:application/octet-stream;base64,{}"}}],
  "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 36}},
                  {{"buffer": 0, "byteOffset": 36, "byteLength": 6}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                  "min": [0, 0, 0], "max": [1, 1, 0]}},
                 {{"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}}]
}})",
                       buffer.size(), base64(buffer));
}

void expectValidMesh(const Mesh& m) {
    EXPECT_TRUE(validateMesh(m, "test")) << validateMesh(m, "test").message();
    for (const glm::vec3& n : m.normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-3f);
}

TEST(Mesh, LoadsSharedModels) {
    struct Expect {
        const char* file;
        std::size_t triangles;
        bool uv;
    };
    for (const Expect e :
         {Expect{"stanford-bunny.obj", 69451, false}, Expect{"spot.obj", 5856, true},
          Expect{"teapot.obj", 6320, false}, Expect{"suzanne.obj", 0, false}}) {
        const auto path = sharedModels() / e.file;
        if (!std::filesystem::exists(path)) MVR_SKIP(ModelsMissing) << "no " << path;
        auto mesh = loadMesh(path);
        ASSERT_TRUE(mesh) << mesh.status().message();
        if (e.triangles) {
            EXPECT_EQ(mesh->triangleCount(), e.triangles) << e.file;
        } else {
            EXPECT_GT(mesh->triangleCount(), 900u) << e.file;  // suzanne: quads and triangles
        }
        EXPECT_EQ(!mesh->texcoords.empty(), e.uv) << e.file;
        expectValidMesh(*mesh);
    }
}

TEST(Mesh, BunnyNormalsPointOutward) {
    const auto path = sharedModels() / "stanford-bunny.obj";
    if (!std::filesystem::exists(path)) MVR_SKIP(ModelsMissing);
    auto mesh = loadMesh(path);
    ASSERT_TRUE(mesh);
    const glm::vec3 c = mesh->bounds().center();
    int outward = 0;
    for (std::size_t i = 0; i < mesh->positions.size(); ++i) {
        outward += glm::dot(mesh->normals[i], mesh->positions[i] - c) > 0.0f;
    }
    EXPECT_GT(outward, int(mesh->positions.size() * 0.8));
}

TEST(Mesh, LoadsObjPlyGltf) {
    TempDir dir;
    auto cube = loadMesh(dir.write("cube.obj", kCubeObj));
    ASSERT_TRUE(cube) << cube.status().message();
    EXPECT_EQ(cube->triangleCount(), 12u);
    expectValidMesh(*cube);
    auto tetra = loadMesh(dir.write("tetra.ply", kTetraPly));
    ASSERT_TRUE(tetra) << tetra.status().message();
    EXPECT_EQ(tetra->triangleCount(), 4u);
    expectValidMesh(*tetra);
    auto tri = loadMesh(dir.write("tri.gltf", triangleGltf()));
    ASSERT_TRUE(tri) << tri.status().message();
    EXPECT_EQ(tri->triangleCount(), 1u);
    EXPECT_NEAR(tri->bounds().min.x, 10.0f, 1e-5f);  // the node transform was applied
    EXPECT_NEAR(tri->normals[0].z, 1.0f, 1e-5f);     // smooth normals generated
}

std::string binaryPly(bool bigEndian) {
    std::string out = fmt::format(
        "ply\nformat {} 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
        "element face 1\nproperty list uchar uint vertex_indices\nend_header\n",
        bigEndian ? "binary_big_endian" : "binary_little_endian");
    auto put = [&](const void* p, std::size_t n) {
        std::string bytes(static_cast<const char*>(p), n);
        if (bigEndian) std::reverse(bytes.begin(), bytes.end());  // this machine is little-endian
        out += bytes;
    };
    const float verts[3][6] = {{0, 0, 0, 0, 0, 2}, {1, 0, 0, 0, 0, 2}, {0, 1, 0, 0, 0, 2}};
    for (const auto& v : verts)
        for (float f : v) put(&f, 4);
    const unsigned char three = 3;
    out += static_cast<char>(three);
    for (std::uint32_t i : {0u, 1u, 2u}) put(&i, 4);
    return out;
}

TEST(Mesh, LoadsBinaryPly) {
    TempDir dir;
    for (bool big : {false, true}) {
        auto tri = loadMesh(dir.write(big ? "be.ply" : "le.ply", binaryPly(big)));
        ASSERT_TRUE(tri) << tri.status().message();
        EXPECT_EQ(tri->triangleCount(), 1u);
        EXPECT_NEAR(tri->normals[0].z, 1.0f, 1e-6f);  // the file's normals, normalized
        const std::string full = binaryPly(big);
        for (std::size_t n = 0; n < full.size(); ++n) {
            auto r = loadMesh(dir.write("cut.ply", full.substr(0, n)));
            EXPECT_FALSE(r) << "prefix " << n << " of " << full.size();
        }
    }
}

TEST(Mesh, LocalityReorderKeepsTriangles) {
    TempDir dir;
    auto cube = loadMesh(dir.write("cube.obj", kCubeObj));
    ASSERT_TRUE(cube);
    // Same set of triangles (as position triples, up to rotation of the corners) after reorder.
    auto key = [](const Mesh& m, std::size_t t) {
        std::array<glm::vec3, 3> p{m.positions[m.indices[t]], m.positions[m.indices[t + 1]],
                                   m.positions[m.indices[t + 2]]};
        int first = 0;
        for (int k = 1; k < 3; ++k) {
            if (std::tie(p[k].x, p[k].y, p[k].z) < std::tie(p[first].x, p[first].y, p[first].z))
                first = k;
        }
        return fmt::format("{},{},{}|{},{},{}|{},{},{}", p[first].x, p[first].y, p[first].z,
                           p[(first + 1) % 3].x, p[(first + 1) % 3].y, p[(first + 1) % 3].z,
                           p[(first + 2) % 3].x, p[(first + 2) % 3].y, p[(first + 2) % 3].z);
    };
    Mesh shuffled = *cube;
    std::vector<std::string> before, after;
    for (std::size_t t = 0; t < shuffled.indices.size(); t += 3) before.push_back(key(shuffled, t));
    std::reverse(shuffled.indices.begin(), shuffled.indices.end());  // also flips winding...
    std::reverse(shuffled.indices.begin(), shuffled.indices.end());  // ...so flip back
    optimizeMeshLocality(shuffled);
    for (std::size_t t = 0; t < shuffled.indices.size(); t += 3) after.push_back(key(shuffled, t));
    std::sort(before.begin(), before.end());
    std::sort(after.begin(), after.end());
    EXPECT_EQ(before, after);
}

TEST(Mesh, BadFilesGiveClearErrors) {
    TempDir dir;
    auto missing = loadMesh(dir.path() / "nope.obj");
    EXPECT_EQ(missing.status().code(), ErrorCode::Input);
    EXPECT_NE(missing.status().message().find("file not found"), std::string::npos);
    EXPECT_NE(loadMesh(dir.path()).status().message().find("not a regular file"),
              std::string::npos);
    EXPECT_NE(loadMesh(dir.write("empty.obj", "")).status().message().find("empty"),
              std::string::npos);
    auto noTris = loadMesh(dir.write("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"));
    EXPECT_FALSE(noTris);
    EXPECT_EQ(noTris.status().code(), ErrorCode::Input);
    auto degenerate = loadMesh(dir.write("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n"));
    EXPECT_FALSE(degenerate);
    auto badIndex = loadMesh(dir.write("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"));
    EXPECT_FALSE(badIndex);
    // An ELF-like header with embedded NULs: the length comes from the literal itself (a
    // hand-counted length once read 2 bytes past its end, which ASan reports).
    static constexpr char kGarbage[] = "\x7f\x45LF\x02\x01\x01\0\0\0garbage\xff\xfe";
    auto garbage = loadMesh(dir.write("garbage.obj", std::string(kGarbage, sizeof kGarbage - 1)));
    EXPECT_FALSE(garbage);
    auto badPly = loadMesh(
        dir.write("bad.ply", "ply\nformat ascii 1.0\nelement vertex 3\nend_header\n0 0\n"));
    EXPECT_FALSE(badPly);
    auto badGltf = loadMesh(dir.write(
        "bad.gltf",
        "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 7}}]}]}"));
    EXPECT_FALSE(badGltf);
    auto nanObj = loadMesh(dir.write("nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
    EXPECT_FALSE(nanObj);
    for (const auto* r :
         {&missing, &noTris, &degenerate, &badIndex, &garbage, &badPly, &badGltf, &nanObj}) {
        EXPECT_NE(r->status().message().find("mvr::loadMesh()"), std::string::npos)
            << r->status().message();
    }
}

/// Every truncated prefix of a small file in each format loads or fails cleanly: never a crash.
TEST(Mesh, SurvivesEveryTruncatedPrefix) {
    TempDir dir;
    const std::pair<const char*, std::string> files[] = {
        {"obj", kCubeObj}, {"ply", kTetraPly}, {"gltf", triangleGltf()}};
    for (const auto& [ext, content] : files) {
        int loaded = 0;
        for (std::size_t n = 0; n < content.size(); ++n) {
            auto r = loadMesh(dir.write(fmt::format("prefix.{}", ext), content.substr(0, n)));
            if (r) {
                ++loaded;
                EXPECT_TRUE(validateMesh(*r, "prefix"));
            } else {
                EXPECT_FALSE(r.status().message().empty());
            }
        }
        EXPECT_LT(loaded, int(content.size())) << ext;  // most prefixes are rejected
    }
}

TEST(Mesh, SurvivesSampledPrefixesOfABigModel) {
    const auto path = sharedModels() / "suzanne.obj";
    if (!std::filesystem::exists(path)) MVR_SKIP(ModelsMissing);
    std::ifstream in(path, std::ios::binary);
    const std::string content((std::istreambuf_iterator<char>(in)), {});
    TempDir dir;
    for (std::size_t n = 0; n < content.size(); n += 1237) {
        auto r = loadMesh(dir.write("part.obj", content.substr(0, n)));
        if (r) {
            EXPECT_TRUE(validateMesh(*r, "part"));
        }
    }
}

TEST(Mesh, SmoothNormalsOfACube) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.indices = {0, 1, 2};
    computeSmoothNormals(m);
    for (const glm::vec3& n : m.normals) EXPECT_NEAR(n.z, 1.0f, 1e-6f);
}

// glTF accessors, buffer views and buffers are checked against each other before assimp reads
// them (model_guard.h checkGltfBounds): assimp 5.2.5 copies an accessor past its buffer view
// (fuzzing: tests/fuzz/regressions/glb/). Each bad file names the culprit; the good one loads.
/// loadMesh() of `file` written as NAME refuses it as Input, naming the file and every part.
void expectRefusedGltf(test::TempDir& dir, const std::string& name, const std::string& file,
                       const std::vector<std::string>& parts) {
    auto r = loadMesh(dir.write(name, file));
    ASSERT_FALSE(r) << name;
    EXPECT_EQ(r.status().code(), ErrorCode::Input) << name;
    EXPECT_NE(r.status().message().find(name), std::string::npos) << r.status().message();
    for (const std::string& part : parts)
        EXPECT_NE(r.status().message().find(part), std::string::npos) << r.status().message();
}

TEST(Mesh, GltfAccessorsMustLieInsideTheirBuffers) {
    // Three vertices (36 bytes) and three uint16 indices (6 bytes, padded to 8).
    const float pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const std::uint16_t idx[] = {0, 1, 2, 0};
    std::string bin(reinterpret_cast<const char*>(pos), sizeof pos);
    bin.append(reinterpret_cast<const char*>(idx), sizeof idx);
    auto gltf = [&](int bufferLength, int posViewLength, int posOffset, const std::string& data) {
        return fmt::format(
            R"({{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],)"
            R"("nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},)"
            R"("indices":1}}]}}],"buffers":[{{"byteLength":{},"uri":"data:application/)"
            R"(octet-stream;base64,{}"}}],"bufferViews":[{{"buffer":0,"byteOffset":0,)"
            R"("byteLength":{}}},{{"buffer":0,"byteOffset":36,"byteLength":6}}],)"
            R"("accessors":[{{"bufferView":0,"byteOffset":{},"componentType":5126,"count":3,)"
            R"("type":"VEC3","min":[0,0,0],"max":[1,1,0]}},{{"bufferView":1,)"
            R"("componentType":5123,"count":3,"type":"SCALAR"}}]}})",
            bufferLength, test::base64(data), posViewLength, posOffset);
    };
    test::TempDir dir;
    auto good = loadMesh(dir.write("good.gltf", gltf(44, 36, 0, bin)));
    ASSERT_TRUE(good) << good.status().message();
    EXPECT_EQ(good->triangleCount(), 1u);
    const struct {
        const char* name;
        std::string file;
        const char* message;
    } bad[] = {
        {"offset.gltf", gltf(44, 36, 1, bin),
         "malformed glTF: accessor 0 (3 elements of 12 bytes from byte 1 of bufferView 0) runs "
         "past its bufferView"},
        {"view.gltf", gltf(44, 60, 0, bin),
         "malformed glTF: bufferView 0 (byteOffset 0, byteLength 60) runs past buffer 0's "
         "44 bytes"},
        {"buffer.gltf", gltf(44, 36, 0, bin.substr(0, 30)),
         "malformed glTF: buffer 0 claims 44 bytes, its data holds 30"},
    };
    for (const auto& b : bad) expectRefusedGltf(dir, b.name, b.file, {b.message});
}

// assimp reads glTF JSON with rapidjson, mvr's bounds check with nlohmann: where the two
// would read a file differently, mvr refuses it, or the check would not cover what assimp
// reads (the CI fuzz run found a 2 TB allocation behind invalid UTF-8, which nlohmann refused
// and rapidjson read). Each message names the reason.
TEST(Mesh, GltfThatAssimpWouldReadDifferentlyIsRefused) {
    const float pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const std::string data =
        test::base64(std::string(reinterpret_cast<const char*>(pos), sizeof pos));
    auto gltf = [&](const std::string& version, const std::string& view,
                    const std::string& name) {
        return fmt::format(
            R"({{"asset":{{"version":"{}"}},"scene":0,"scenes":[{{"nodes":[0],"name":"{}"}}],)"
            R"("nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],)"
            R"("buffers":[{{"byteLength":36,"uri":"data:application/octet-stream;base64,{}"}}],)"
            R"("bufferViews":[{}],"accessors":[{{"bufferView":0,"componentType":5126,"count":3,)"
            R"("type":"VEC3","min":[0,0,0],"max":[1,1,0]}}]}})",
            version, name, data, view);
    };
    const std::string view = R"({"buffer":0,"byteLength":36})";
    test::TempDir dir;
    // A NUL byte ends the document for assimp, and for the check: what follows is not read.
    auto nul = loadMesh(dir.write("nul.gltf", gltf("2.0", view, "s") + std::string(1, '\0') + "junk"));
    ASSERT_TRUE(nul) << nul.status().message();
    EXPECT_EQ(nul->triangleCount(), 1u);

    std::string glb1("glTF\x01\0\0\0\x20\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0\0", 32);
    const struct {
        const char* name;
        std::string file;
        const char* message;
        const char* also = "";
    } bad[] = {
        {"utf8.gltf", gltf("2.0", view, "caf\xe9"),
         "malformed glTF: its JSON: parse error at line 1, column ", "ill-formed UTF-8 byte"},
        {"twice.gltf", gltf("2.0", R"({"buffer":0,"byteLength":36,"byteLength":12})", "s"),
         "malformed glTF: an object names the key \"byteLength\" twice"},
        {"v1.gltf", gltf("1.0", view, "s"),
         "malformed glTF: glTF 1.0 is not supported (mvr reads glTF 2.0)"},
        {"noversion.gltf", R"({"asset":{},"scenes":[]})",
         "malformed glTF: no asset.version (glTF 2.0 requires one)"},
        {"v1.glb", glb1, "binary glTF 1.0 is not supported (mvr reads glTF 2.0)"},
        {"mime.gltf",
         R"({"asset":{"version":"2.0"},"images":[{"bufferView":0,"mimeType":"image+png"}]})",
         "malformed glTF: image 0's mimeType \"image+png\" is not type/subtype"},
        {"mediatype.gltf",
         R"({"asset":{"version":"2.0"},"images":[{"uri":"data:png;base64,AAAA"}]})",
         "malformed glTF: image 0 has a data URI of media type \"png\" (not type/subtype)"},
        {"header.gltf",
         R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":3,"uri":"data:application/)" +
             std::string(120, 'x') + R"(;base64,AAAA"}]})",
         "malformed glTF: buffer 0 has a data URI header of 144 bytes (at most 100)"},
        {"loop.gltf",
         R"({"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":0},)"
         R"("indices":0,"mode":2}]}],"accessors":[{"count":3}]})",
         "malformed glTF: mesh 0 primitive 0 is an indexed LINE_LOOP (mode 2)"},
        {"noposition.gltf",
         R"({"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"NORMAL":0}}]}],)"
         R"("accessors":[{"count":3}]})",
         "malformed glTF: mesh 0 primitive 0 has no POSITION accessor"},
        {"fan.gltf",
         R"({"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":0},)"
         R"("mode":6}]}],"accessors":[{"count":1}]})",
         "malformed glTF: mesh 0 primitive 0 is a TRIANGLE_FAN of 1 vertices (one triangle needs 3)"},
        {"zeros.gltf",
         R"({"asset":{"version":"2.0"},"accessors":[{"componentType":5126,"count":4000000000,)"
         R"("type":"VEC3","sparse":{"count":0}}]})",
         "malformed glTF: accessor 0 has no bufferView and 4000000000 elements of 12 bytes: "
         "over 256 MiB of zeros"},
    };
    for (const auto& b : bad) expectRefusedGltf(dir, b.name, b.file, {b.message, b.also});
}

}  // namespace
}  // namespace mvr

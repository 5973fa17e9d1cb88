// Real-world variants of each format load like their plain equivalents: PLY tristrips with -1
// restarts, list count/index types, extra properties, colors, ascii and both binary orders; OBJ
// negative indices, n-gons, missing normals/texture coordinates, CRLF, `\` continuations; glTF
// several primitives, sparse accessors, non-indexed geometry, 8/16/32-bit indices. "Like": the
// same set of triangles (positions, winding kept) once the loader has reordered them.
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <fstream>
#include <string>
#include <tuple>
#include <vector>

#include <fmt/core.h>
#include <gtest/gtest.h>

#include "test_files.h"

#include "mvr/core/mesh.h"
#include "mvr/io/mesh_io.h"

namespace mvr {
namespace {

using test::TempDir;

using Corner = std::tuple<float, float, float>;
using Triangle = std::array<Corner, 3>;

/// The mesh's triangles as positions, each rotated to start at its smallest corner (winding
/// kept), sorted: equal for two loads of the same geometry whatever the vertex order.
std::vector<Triangle> triangles(const Mesh& m) {
    std::vector<Triangle> out;
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
        Triangle tri;
        for (int k = 0; k < 3; ++k) {
            const glm::vec3 p = m.positions[m.indices[t + k]];
            tri[k] = {p.x, p.y, p.z};
        }
        std::rotate(tri.begin(), std::min_element(tri.begin(), tri.end()), tri.end());
        out.push_back(tri);
    }
    std::sort(out.begin(), out.end());
    return out;
}

Mesh load(const std::filesystem::path& path) {
    auto m = loadMesh(path);
    EXPECT_TRUE(m) << path << ": " << m.status().message();
    return m ? std::move(m).value() : Mesh{};
}

// ---- PLY ----

// A 3x2 grid of vertices (0..5) and a triangle above it (6..8).
const float kGrid[9][3] = {{0, 1, 0}, {0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {2, 1, 0},
                           {2, 0, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
// One strip over the grid, a restart, a second strip ending in a degenerate joint.
const std::vector<int> kStrip = {1, 0, 3, 2, 5, 4, -1, 6, 7, 8, 8};
// The same triangles by hand: triangle i of a strip (a, b, c) is (b, a, c) for odd i.
const std::vector<std::array<int, 3>> kStripTriangles = {
    {1, 0, 3}, {3, 0, 2}, {3, 2, 5}, {5, 2, 4}, {6, 7, 8}};

struct PlyLayout {
    std::string format = "ascii";  // ascii, binary_little_endian, binary_big_endian
    std::string countType = "uchar";
    std::string indexType = "int";
    bool extras = false;  // a property before x, colors, a face property after the list
    bool strips = false;
};

class PlyWriter {
public:
    explicit PlyWriter(const std::string& format) : mFormat(format) {}
    void value(const std::string& type, double v) {
        if (mFormat == "ascii") {
            mBody += fmt::format("{} ", v);
            return;
        }
        unsigned char b[8];
        std::size_t n = 4;
        if (type == "uchar") {
            b[0] = static_cast<unsigned char>(v), n = 1;
        } else if (type == "int") {
            const auto x = static_cast<std::int32_t>(v);
            std::memcpy(b, &x, 4);
        } else if (type == "uint") {
            const auto x = static_cast<std::uint32_t>(static_cast<std::int64_t>(v));
            std::memcpy(b, &x, 4);
        } else {
            const auto x = static_cast<float>(v);
            std::memcpy(b, &x, 4);
        }
        const bool little = std::endian::native == std::endian::little;
        if ((mFormat == "binary_little_endian") != little) std::reverse(b, b + n);
        mBody.append(reinterpret_cast<const char*>(b), n);
    }
    void endRow() {
        if (mFormat == "ascii") mBody += "\n";
    }
    std::string mBody;

private:
    std::string mFormat;
};

std::string ply(const PlyLayout& l) {
    std::string h = fmt::format("ply\nformat {} 1.0\ncomment made by mvr's tests\n", l.format);
    h += "element vertex 9\n";
    if (l.extras) h += "property float confidence\n";
    h += "property float x\nproperty float y\nproperty float z\n";
    if (l.extras) h += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    PlyWriter w(l.format);
    for (int v = 0; v < 9; ++v) {
        if (l.extras) w.value("float", 0.5);
        for (int k = 0; k < 3; ++k) w.value("float", kGrid[v][k]);
        if (l.extras)
            for (int k = 0; k < 3; ++k) w.value("uchar", 40 * v);
        w.endRow();
    }
    const std::string list =
        fmt::format("property list {} {} vertex_indices\n", l.countType, l.indexType);
    if (l.strips) {
        h += "element tristrips 1\n" + list;
        w.value(l.countType, double(kStrip.size()));
        for (int i : kStrip) w.value(l.indexType, i);
        w.endRow();
    } else {
        h += fmt::format("element face {}\n", kStripTriangles.size()) + list;
        if (l.extras) h += "property uchar flags\n";
        for (const auto& t : kStripTriangles) {
            w.value(l.countType, 3);
            for (int i : t) w.value(l.indexType, i);
            if (l.extras) w.value("uchar", 7);
            w.endRow();
        }
    }
    return h + "end_header\n" + w.mBody;
}

TEST(MeshVariants, PlyLayoutsLoadLikeThePlainFile) {
    TempDir dir("mvr-variants-test");
    const Mesh plain = load(dir.write("plain.ply", ply({})));
    ASSERT_EQ(plain.triangleCount(), kStripTriangles.size());
    const auto expected = triangles(plain);
    int n = 0;
    for (const char* format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
        for (const char* countType : {"uchar", "int", "uint"}) {
            for (const char* indexType : {"int", "uint"}) {
                for (const bool extras : {false, true}) {
                    for (const bool strips : {false, true}) {
                        // A uint strip writes -1 as 4294967295 (binary): the same restart.
                        const PlyLayout l{format, countType, indexType, extras, strips};
                        const auto path = dir.write(fmt::format("v{}.ply", n++), ply(l));
                        const Mesh m = load(path);
                        EXPECT_EQ(triangles(m), expected)
                            << format << " " << countType << " " << indexType
                            << (extras ? " extras" : "") << (strips ? " tristrips" : "");
                    }
                }
            }
        }
    }
}

// Blender 2.47's PLY exporter wrote "Created by Blender3D 247 - www.blender.org, source file: "
// as a header line of its own, without "comment": the line is skipped with a warning naming it
// (assimp skips unknown header lines too), and the mesh is the plain file's.
TEST(MeshVariants, PlyHeaderLinesThatAreNoKeywordAreSkippedWithAWarning) {
    TempDir dir("mvr-variants-test");
    const Mesh plain = load(dir.write("plain.ply", ply({})));
    std::string text = ply({});
    const std::string blender = "Created by Blender3D 247 - www.blender.org, source file: ";
    text.insert(text.find('\n', text.find("format")) + 1, blender + "\n");
    const auto path = dir.write("blender.ply", text);
    std::vector<std::string> warnings;
    auto m = loadMesh(path, &warnings);
    ASSERT_TRUE(m) << m.status().message();
    EXPECT_EQ(triangles(*m), triangles(plain));
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("PLY header line 3: '" + blender +
                               "' is not a PLY keyword (a comment without 'comment'?): skipped"),
              std::string::npos)
        << warnings[0];
}

TEST(MeshVariants, PlyTristripsKeepTheirWinding) {
    // A strip's odd triangles are flipped back: every triangle of the grid faces +z or -z the
    // same way as the first.
    TempDir dir("mvr-variants-test");
    const Mesh m = load(dir.write("strip.ply", ply({.strips = true})));
    ASSERT_EQ(m.triangleCount(), 5u);  // the degenerate joint is dropped
    int up = 0;
    for (std::size_t t = 0; t < 12; t += 3) {
        const glm::vec3 a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]],
                        c = m.positions[m.indices[t + 2]];
        if (a.z == 0 && b.z == 0 && c.z == 0) up += glm::cross(b - a, c - a).z > 0 ? 1 : -1;
    }
    EXPECT_EQ(std::abs(up), 4);
}

TEST(MeshVariants, PlyHeadersThatClaimTooMuchAreRefused) {
    TempDir dir("mvr-variants-test");
    // An element count, and a list length, that the file cannot hold: refused before allocating.
    auto count = loadMesh(dir.write(
        "count.ply",
        "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
        "property float y\nproperty float z\nend_header\n0000"));
    ASSERT_FALSE(count);
    EXPECT_NE(count.status().message().find("too short"), std::string::npos)
        << count.status().message();
    PlyLayout l{.format = "binary_little_endian", .countType = "uint", .strips = true};
    std::string strip = ply(l);
    const std::size_t at = strip.find("end_header\n") + 11 + 9 * 12;
    const std::uint32_t huge = 2000000000u;
    strip.replace(at, 4, reinterpret_cast<const char*>(&huge), 4);
    auto list = loadMesh(dir.write("list.ply", strip));
    ASSERT_FALSE(list);
    EXPECT_NE(list.status().message().find("tristrips 0 of 1: list of 2000000000 items"),
              std::string::npos)
        << list.status().message();
    auto nan = loadMesh(
        dir.write("nan.ply",
                  "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                  "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                  "end_header\n0 0 0\n1 0 0\n0 nan 0\n3 0 1 2\n"));
    ASSERT_FALSE(nan);
    EXPECT_NE(nan.status().message().find("nan.ply: vertex 2 of 3 has a NaN coordinate"),
              std::string::npos)
        << nan.status().message();
}

// ---- OBJ ----

const char* kPlainObj =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\n"
    "f 1 2 3\nf 1 3 4\nf 1 2 6\nf 1 6 5\n";

TEST(MeshVariants, ObjVariantsLoadLikeThePlainFile) {
    TempDir dir("mvr-variants-test");
    const auto expected = triangles(load(dir.write("plain.obj", kPlainObj)));
    ASSERT_EQ(expected.size(), 4u);
    const std::vector<std::pair<std::string, std::string>> variants = {
        {"negative",
         "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf -4 -3 -2\nf -4 -2 -1\n"
         "v 0 0 1\nv 1 0 1\nf -6 -5 -1\nf -6 -1 -2\n"},
        {"ngons",
         "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\n"
         "f 1 2 3 4\nf 1 2 6 5\n"},
        {"uv-only",
         "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nvt 0 0\nvt 1 1\n"
         "f 1/1 2/2 3/1\nf 1/1 3/1 4/2\nf 1/1 2/2 6/1\nf 1/2 6/1 5/2\n"},
        {"normals-only",
         "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nvn 0 0 1\n"
         "vn 0 -1 0\nf 1//1 2//1 3//1\nf 1//1 3//1 4//1\nf 1//2 2//2 6//2\n"
         "f 1//2 6//2 5//2\n"},
        {"full",
         "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nvt 0 0\nvn 0 0 1\n"
         "f 1/1/1 2/1/1 3/1/1\nf 1/1/1 3/1/1 4/1/1\nf 1/1/1 2/1/1 6/1/1\n"
         "f 1/1/1 6/1/1 5/1/1\n"},
        {"crlf",
         "v 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0\r\nv 0 0 1\r\nv 1 0 1\r\n"
         "f 1 2 3\r\nf 1 3 4\r\nf 1 2 6\r\nf 1 6 5\r\n"},
        {"continuation",
         "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\n"
         "f 1 2 \\\n3\nf 1 3 4\nf 1 \\\n 2 \\\n 6\nf 1 6 5\n"},
        {"continuation-crlf",
         "v 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0\r\nv 0 0 1\r\nv 1 0 1\r\n"
         "f 1 2 \\\r\n3\r\nf 1 3 4\r\nf 1 2 6\r\nf 1 6 5\r\n"},
    };
    for (const auto& [name, text] : variants) {
        const Mesh m = load(dir.write(name + ".obj", text));
        EXPECT_EQ(triangles(m), expected) << name;
    }
}

TEST(MeshVariants, ObjRefusalsNameTheLine) {
    TempDir dir("mvr-variants-test");
    auto nan = loadMesh(dir.write("nan.obj",
                                  "# a comment\nv 0 0 0\nv 1 0 0\nv 0 1 nan\n"
                                  "f 1 2 3\n"));
    ASSERT_FALSE(nan);
    EXPECT_NE(nan.status().message().find("nan.obj: line 4: vertex 3 has a NaN coordinate"),
              std::string::npos)
        << nan.status().message();
    auto inf = loadMesh(dir.write("inf.obj", "v 0 0 0\nv 1 \\\n inf 0\nv 0 1 0\nf 1 2 3\n"));
    ASSERT_FALSE(inf);
    EXPECT_NE(inf.status().message().find("line 2: vertex 2 has an infinite coordinate"),
              std::string::npos)
        << inf.status().message();
    auto flat = loadMesh(dir.write("flat.obj", "v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 2 3\n"));
    ASSERT_FALSE(flat);
    EXPECT_NE(flat.status().message().find("flat.obj: is degenerate"), std::string::npos)
        << flat.status().message();
}

// ---- glTF ----

using test::base64;

template <typename T>
void append(std::string& buffer, const std::vector<T>& values) {
    buffer.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
    buffer.append((4 - buffer.size() % 4) % 4, '\0');
}

// Two triangles of a quad, and a third one apart: the geometry of every glTF variant.
const std::vector<float> kQuad = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
const std::vector<int> kQuadIndices = {0, 1, 2, 0, 2, 3};
const std::vector<float> kApart = {0, 0, 2, 1, 0, 2, 0, 1, 2};

std::string gltf(const std::string& buffer, const std::string& views, const std::string& accessors,
                 const std::string& primitives) {
    return fmt::format(
        R"({{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
  "nodes": [{{"mesh": 0}}], "meshes": [{{"primitives": [{}]}}],
  "buffers": [{{"byteLength": {}, "uri": "data:application/octet-stream;base64,{}"}}],
  "bufferViews": [{}], "accessors": [{}]}})",
        primitives, buffer.size(), base64(buffer), views, accessors);
}

std::string view(std::size_t offset, std::size_t length) {
    return fmt::format(R"({{"buffer": 0, "byteOffset": {}, "byteLength": {}}})", offset, length);
}

std::string positions(int viewIndex, int count, const std::string& extra = "") {
    return fmt::format(
        R"({{"bufferView": {}, "componentType": 5126, "count": {}, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 2]{}}})",
        viewIndex, count, extra);
}

/// The quad indexed with `componentType` (5121, 5123, 5125) and the apart triangle
/// non-indexed, as two primitives.
std::string indexedGltf(int componentType) {
    std::string buffer;
    append(buffer, kQuad);
    const std::size_t quadBytes = buffer.size();
    std::size_t indexBytes = 0;
    if (componentType == 5121) {
        append(buffer, std::vector<std::uint8_t>(kQuadIndices.begin(), kQuadIndices.end()));
        indexBytes = 6;
    } else if (componentType == 5123) {
        append(buffer, std::vector<std::uint16_t>(kQuadIndices.begin(), kQuadIndices.end()));
        indexBytes = 12;
    } else {
        append(buffer, std::vector<std::uint32_t>(kQuadIndices.begin(), kQuadIndices.end()));
        indexBytes = 24;
    }
    const std::size_t apartAt = buffer.size();
    append(buffer, kApart);
    return gltf(
        buffer,
        view(0, quadBytes) + "," + view(quadBytes, indexBytes) + "," +
            view(apartAt, kApart.size() * 4),
        positions(0, 4) + "," +
            fmt::format(R"({{"bufferView": 1, "componentType": {}, "count": 6, "type": "SCALAR"}})",
                        componentType) +
            "," + positions(2, 3),
        R"({"attributes": {"POSITION": 0}, "indices": 1}, {"attributes": {"POSITION": 2}})");
}

/// All six quad corners and the apart triangle non-indexed in one primitive; the quad's
/// positions come from a sparse accessor over zeros.
std::string sparseGltf() {
    std::vector<float> corners;
    for (int i : kQuadIndices)
        corners.insert(corners.end(), kQuad.begin() + 3 * i, kQuad.begin() + 3 * i + 3);
    corners.insert(corners.end(), kApart.begin(), kApart.end());
    std::string buffer;
    append(buffer, std::vector<float>(corners.size(), 0.0f));  // the base: all zeros
    const std::size_t idxAt = buffer.size();
    std::vector<std::uint16_t> which;
    for (std::uint16_t i = 0; i < 9; ++i) which.push_back(i);
    append(buffer, which);
    const std::size_t valAt = buffer.size();
    append(buffer, corners);
    const std::string sparse = fmt::format(
        R"(, "sparse": {{"count": 9, "indices": {{"bufferView": 1, "componentType": 5123}}, "values": {{"bufferView": 2}}}})");
    return gltf(buffer,
                view(0, idxAt) + "," + view(idxAt, 18) + "," + view(valAt, corners.size() * 4),
                positions(0, 9, sparse), R"({"attributes": {"POSITION": 0}})");
}

TEST(MeshVariants, GltfVariantsLoadLikeThePlainFile) {
    TempDir dir("mvr-variants-test");
    const auto expected = triangles(load(dir.write("plain.gltf", indexedGltf(5123))));
    ASSERT_EQ(expected.size(), 3u);
    EXPECT_EQ(triangles(load(dir.write("u8.gltf", indexedGltf(5121)))), expected) << "8-bit";
    EXPECT_EQ(triangles(load(dir.write("u32.gltf", indexedGltf(5125)))), expected) << "32-bit";
    EXPECT_EQ(triangles(load(dir.write("sparse.gltf", sparseGltf()))), expected) << "sparse";
}

}  // namespace
}  // namespace mvr

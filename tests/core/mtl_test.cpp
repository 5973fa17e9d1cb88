// mvr's own MTL reader: Kd, map_Kd (options dropped), d / Tr, errors with file and line, and an
// OBJ's mtllib libraries resolved beside it.
#include "mvr/io/mtl.h"

#include <gtest/gtest.h>

#include "test_files.h"

namespace mvr {
namespace {

TEST(Mtl, ReadsDiffuseColorTextureAndDissolve) {
    const auto m = parseMtl(
        "# two materials\nnewmtl red\nKa 0.1 0 0\nKd 1 0 0\nNs 32\nillum 2\n"
        "map_Kd -s 1 1 1 -clamp on textures/red brick.png\n"
        "newmtl blue\r\nKd 0 0 2\r\nTr 0.25\r\nmap_Bump -bm 0.5 bump.png\r\n"
        "newmtl grey\nKd 0.5\nd -halo 0.5\n",
        "t.mtl");
    ASSERT_TRUE(m) << m.status().message();
    ASSERT_EQ(m->size(), 3u);
    EXPECT_EQ((*m)[0].name, "red");
    EXPECT_EQ((*m)[0].diffuse, glm::vec3(1, 0, 0));
    EXPECT_EQ((*m)[0].diffuseMap, "textures/red brick.png");
    EXPECT_EQ((*m)[0].dissolve, 1.0f);
    EXPECT_EQ((*m)[1].diffuse, glm::vec3(0, 0, 1));  // clamped
    EXPECT_FLOAT_EQ((*m)[1].dissolve, 0.75f);
    EXPECT_TRUE((*m)[1].diffuseMap.empty());  // map_Bump is not the diffuse map
    EXPECT_EQ((*m)[2].diffuse, glm::vec3(0.5f));
    EXPECT_FLOAT_EQ((*m)[2].dissolve, 0.5f);
    EXPECT_EQ(findMtl(*m, "blue"), &(*m)[1]);
    EXPECT_EQ(findMtl(*m, "green"), nullptr);
}

TEST(Mtl, ErrorsNameFileLineAndProblem) {
    const struct {
        const char* text;
        const char* message;
    } cases[] = {
        {"Kd 1 0 0\n", "mvr::parseMtl(): t.mtl:1: Kd before any newmtl"},
        {"newmtl\n", "mvr::parseMtl(): t.mtl:1: newmtl without a name"},
        {"newmtl a\n\nKd 1 x 0\n", "mvr::parseMtl(): t.mtl:3: Kd value 'x' is not a finite number"},
        {"newmtl a\nKd 1 0\n", "mvr::parseMtl(): t.mtl:2: Kd needs 1 or 3 numbers"},
        {"newmtl a\nKd nan 0 0\n",
         "mvr::parseMtl(): t.mtl:2: Kd value 'nan' is not a finite number"},
        {"newmtl a\nd\n", "mvr::parseMtl(): t.mtl:2: d needs one finite number"},
        {"newmtl a\nmap_Kd -s 1 2 3\n", "mvr::parseMtl(): t.mtl:2: map_Kd without a file name"},
        {"newmtl a\nKd spectral x.rfl\n",
         "mvr::parseMtl(): t.mtl:2: Kd spectral / xyz is not supported (give r g b)"},
    };
    for (const auto& c : cases) {
        const auto m = parseMtl(c.text, "t.mtl");
        ASSERT_FALSE(m) << c.text;
        EXPECT_EQ(m.status().code(), ErrorCode::Input);
        EXPECT_EQ(m.status().message(), c.message);
    }
}

TEST(Mtl, ObjLibrariesResolveBesideTheObj) {
    test::TempDir dir("mvr-mtl-test");
    dir.write("a.mtl", "newmtl red\nKd 1 0 0\nmap_Kd red.png\n");
    dir.write("b.mtl", "newmtl blue\nKd 0 0 1\n");
    const auto obj = dir.write("m.obj", "mtllib a.mtl b.mtl\nv 0 0 0\nusemtl red\n");
    const auto m = loadObjMaterials(obj);
    ASSERT_TRUE(m) << m.status().message();
    ASSERT_EQ(m->size(), 2u);
    EXPECT_EQ((*m)[0].diffuseMap, "red.png");
    EXPECT_EQ((*m)[1].name, "blue");

    const auto missing = dir.write("n.obj", "mtllib none.mtl\n");
    const auto e = loadObjMaterials(missing);
    ASSERT_FALSE(e);
    EXPECT_EQ(e.status().message(),
              "mvr::loadMtl(): " + (dir.path() / "none.mtl").string() + ": file not found");
    const auto noLib = loadObjMaterials(dir.write("p.obj", "v 0 0 0\n"));
    ASSERT_TRUE(noLib);
    EXPECT_TRUE(noLib->empty());
}

}  // namespace
}  // namespace mvr

// Scenes: the procedural default scene and grids of copies.
#include "mvr/core/scene.h"

#include <gtest/gtest.h>

namespace mvr {
namespace {

TEST(Scene, DefaultSceneIsValidAndOutwardFacing) {
    const Scene s = makeDefaultScene();
    ASSERT_TRUE(validateScene(s)) << validateScene(s).message();
    EXPECT_GT(s.triangleCount(), 1000u);
    EXPECT_LE(s.lights.size(), std::size_t(kMaxLights));
    // Every closed procedural mesh (sphere, torus, box) winds counter-clockwise seen from outside:
    // the geometric normal agrees with the stored vertex normal.
    for (const Mesh& m : s.meshes) {
        int agree = 0;
        for (std::size_t t = 0; t < m.indices.size(); t += 3) {
            const glm::vec3 a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]],
                            c = m.positions[m.indices[t + 2]];
            const glm::vec3 n = glm::cross(b - a, c - a);
            agree += glm::dot(n, m.normals[m.indices[t]] + m.normals[m.indices[t + 1]] +
                                     m.normals[m.indices[t + 2]]) > 0.0f;
        }
        EXPECT_EQ(agree, int(m.triangleCount())) << m.name;
    }
    // Objects lie in front of and behind the plane through the origin (the default convergence).
    const Bounds b = s.bounds();
    EXPECT_LT(b.min.z, -1.0f);
    EXPECT_GT(b.max.z, 1.0f);
}

TEST(Scene, GridHasCopiesSideBySide) {
    Mesh tri;
    tri.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    tri.normals.assign(3, {0, 0, 1});
    tri.indices = {0, 1, 2};
    for (int k : {1, 3, 5, 9}) {
        const Scene s = makeGridScene({tri}, k);
        EXPECT_EQ(s.instances.size(), std::size_t(k));
        EXPECT_EQ(s.triangleCount(), std::size_t(k));
        // No two copies at the same place.
        for (int i = 0; i < k; ++i)
            for (int j = i + 1; j < k; ++j)
                EXPECT_GT(glm::length(glm::vec3(s.instances[i].worldFromModel[3] -
                                                s.instances[j].worldFromModel[3])),
                          0.5f);
    }
}

TEST(Scene, ValidateRejectsBrokenScenes) {
    Scene empty;
    EXPECT_FALSE(validateScene(empty));
    Scene s = makeDefaultScene();
    s.instances[0].mesh = 99;
    EXPECT_NE(validateScene(s).message().find("mesh 99"), std::string::npos);
    s = makeDefaultScene();
    s.lights.resize(kMaxLights + 1);
    EXPECT_FALSE(validateScene(s));
}

}  // namespace
}  // namespace mvr

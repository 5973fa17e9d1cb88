// The exactness check several raster tests share: soft:unified == soft:multipass bit for bit.
#pragma once

#include <initializer_list>
#include <utility>

#include <gtest/gtest.h>

#include "mvr/core/render.h"
#include "mvr/core/rig.h"
#include "mvr/core/scene.h"

namespace mvr::raster::test {

/// `scene` rendered by `backend`'s unified and multipass methods, bit for bit alike in every
/// view, in flat, vertex and pixel shading (vertex with back faces culled when `cullVertex`),
/// for each (columns, rows) of `grids`: an off-axis rig from (0.5, 1.8, 6), interaxial 0.2,
/// converged at 6, views of width × height.
inline void expectUnifiedEqualsMultipass(Backend& backend, const Scene& scene,
                                         std::initializer_list<std::pair<int, int>> grids,
                                         int width, int height, bool cullVertex = false) {
    Camera cam;
    cam.position = {0.5f, 1.8f, 6.0f};
    cam.aspect = float(width) / float(height);
    for (auto [c, r] : grids) {
        RigParams p;
        p.columns = c, p.rows = r, p.interaxial = 0.2f, p.convergence = 6.0f;
        auto rig = makeRig(cam, p);
        ASSERT_TRUE(rig) << rig.status().message();
        for (int mode = 0; mode < 3; ++mode) {
            RenderSettings s;
            s.width = width, s.height = height;
            s.shading = Shading(mode);
            s.cullBackFaces = cullVertex && mode == 1;
            auto mp = backend.render(scene, *rig, s, "multipass");
            auto un = backend.render(scene, *rig, s, "unified");
            ASSERT_TRUE(mp && un);
            for (std::size_t v = 0; v < mp->color.size(); ++v) {
                EXPECT_EQ(mp->color[v].rgba, un->color[v].rgba)
                    << c << "x" << r << " view " << v << " shading " << mode;
            }
        }
    }
}

}  // namespace mvr::raster::test

// The rgbd format (mvr/composite/rgbd.h): the depth image's formula, the layout for each depth
// position, its size rules and the sidecar's Bridge fields.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "mvr/composite/compose.h"
#include "mvr/composite/rgbd.h"
#include "test_views.h"

namespace mvr::composite {
namespace {

using test::tag;
using test::taggedViews;

TEST(Rgbd, DepthImageIsLinearInDistanceWhiteNear) {
    const double near = 2.0, far = 12.0;
    const float inf = std::numeric_limits<float>::infinity();
    const std::vector<float> d = {2.0f, 12.0f, 7.0f, 4.5f, 1.0f, 20.0f, inf, 9.96f};
    const Image img = rgbdDepthImage(d, 4, 2, near, far);
    ASSERT_EQ(img.width, 4);
    ASSERT_EQ(img.height, 2);
    // g = round(255 (far - d) / (far - near)), clamped; nothing drawn (inf) black.
    const int expected[] = {255, 0, 128, 191, 255, 0, 0, 52};
    for (int i = 0; i < 8; ++i) {
        const Rgba8 p = img.at(i % 4, i / 4);
        EXPECT_EQ(p.r, expected[i]) << i;
        EXPECT_EQ(p.g, p.r);
        EXPECT_EQ(p.b, p.r);
        EXPECT_EQ(p.a, 255);
        // and decodes back within half a step where it is in range
        if (i < 4 || i == 7) {
            EXPECT_NEAR(far - p.r / 255.0 * (far - near), d[std::size_t(i)],
                        (far - near) / 510.0 + 1e-6);
        }
    }
}

TEST(Rgbd, LayoutFollowsTheDepthPosition) {
    const auto pair = taggedViews(2, 5, 3);  // view 0: the colour, view 1: the depth
    for (auto [position, w, h, colourAt, depthAt] :
         {std::tuple{DepthPosition::Right, 10, 3, std::pair{0, 0}, std::pair{5, 0}},
          std::tuple{DepthPosition::Left, 10, 3, std::pair{5, 0}, std::pair{0, 0}},
          std::tuple{DepthPosition::Top, 5, 6, std::pair{0, 3}, std::pair{0, 0}},
          std::tuple{DepthPosition::Bottom, 5, 6, std::pair{0, 0}, std::pair{0, 3}}}) {
        for (bool swap : {false, true}) {  // --swap-eyes does not reorder colour and depth
            ComposeOptions o;
            o.rgbdDepth = position;
            o.swapEyes = swap;
            auto img = compose("rgbd", pair, o);
            ASSERT_TRUE(img) << img.status().message();
            ASSERT_EQ(img->width, w);
            ASSERT_EQ(img->height, h);
            auto size = outputSize("rgbd", 2, 5, 3, o);
            ASSERT_TRUE(size);
            EXPECT_EQ(size->width, w);
            EXPECT_EQ(size->height, h);
            for (int y = 0; y < 3; ++y) {
                for (int x = 0; x < 5; ++x) {
                    EXPECT_EQ(img->at(colourAt.first + x, colourAt.second + y), tag(0, x, y));
                    EXPECT_EQ(img->at(depthAt.first + x, depthAt.second + y), tag(1, x, y));
                }
            }
            auto largest = largestViewSize("rgbd", 2, w, h, o);
            ASSERT_TRUE(largest);
            EXPECT_EQ(largest->width, 5);
            EXPECT_EQ(largest->height, 3);
        }
    }
}

TEST(Rgbd, TakesExactlyTwoImages) {
    auto one = compose("rgbd", taggedViews(1, 4, 4));
    ASSERT_FALSE(one);
    EXPECT_EQ(one.status().code(), ErrorCode::Usage);
    auto info = findFormat("rgbd");
    ASSERT_TRUE(info);
    EXPECT_TRUE(info->colourAndDepth);
    EXPECT_EQ(info->gpu, GpuPlan::None);
}

TEST(Rgbd, DepthPositionsAndBridgeDepthLoc) {
    // bridge.js, schema.hologram.ts: depth_loc 0 top, 1 bottom, 2 right, 3 left.
    EXPECT_EQ(bridgeDepthLoc(DepthPosition::Top), 0);
    EXPECT_EQ(bridgeDepthLoc(DepthPosition::Bottom), 1);
    EXPECT_EQ(bridgeDepthLoc(DepthPosition::Right), 2);
    EXPECT_EQ(bridgeDepthLoc(DepthPosition::Left), 3);
    for (const char* name : {"right", "left", "top", "bottom"}) {
        auto p = parseDepthPosition(name);
        ASSERT_TRUE(p);
        EXPECT_EQ(depthPositionName(*p), name);
    }
    auto bad = parseDepthPosition("middle");
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.status().message(),
              "--rgbd-depth-position 'middle': expected right, left, top or bottom");
}

TEST(Rgbd, SidecarHoldsBridgesFields) {
    ComposeOptions o;
    o.depthiness = 0.8;
    o.focus = 0.02;
    o.rgbdDepth = DepthPosition::Bottom;
    const std::string json = rgbdSidecarJson(o, {"rgbd.png", 640, 480, 3.5, 9.25, 4});
    for (const char* field :
         {"\"type\": \"rgbd\"", "\"uri\": \"rgbd.png\"", "\"depthiness\": 0.8", "\"focus\": 0.02",
          "\"depth_loc\": 1", "\"depth_inversion\": 0", "\"chroma_depth\": 0", "\"zoom\": 1",
          "\"aspect\": 1.3333333333333333", "\"view\": 4", "\"near\": 3.5", "\"far\": 9.25"})
        EXPECT_NE(json.find(field), std::string::npos) << field << "\n" << json;
}

}  // namespace
}  // namespace mvr::composite

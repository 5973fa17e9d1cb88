// The viewpoint a recipe gives (mvr/session/camera.h: --azimuth / --elevation / --distance /
// --target, --camera-position / --look-at / --up, --camera-matrix, --focal-length-mm) and the
// background: where things land is computed here, not through the code under test.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/core.h>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "mvr/session/camera.h"
#include "mvr/session/render.h"

namespace mvr::session {
namespace {

namespace fs = std::filesystem;

/// An OBJ box lo..hi with material `mtl`, its vertices numbered from `base` (1-based).
std::string objBox(glm::vec3 lo, glm::vec3 hi, const std::string& mtl, int base) {
    std::string s = fmt::format("usemtl {}\n", mtl);
    for (int i = 0; i < 8; ++i) {
        s += fmt::format("v {} {} {}\n", i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y,
                         i & 4 ? hi.z : lo.z);
    }
    // Counter-clockwise seen from outside: -x, +x, -y, +y, -z, +z.
    const int f[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                         {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (const auto& q : f) {
        s += fmt::format("f {} {} {} {}\n", base + q[0], base + q[1], base + q[2], base + q[3]);
    }
    return s;
}

/// An OBJ square of side 2·half facing +Z at `centre` (a plane parallel to the image: its
/// projection's centroid is its centre's projection), vertices numbered from `base`.
std::string objSquare(glm::vec3 centre, float half, const std::string& mtl, int base) {
    std::string s = fmt::format("usemtl {}\n", mtl);
    for (const glm::vec2 c : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)})
        s += fmt::format("v {} {} {}\n", centre.x + half * c.x, centre.y + half * c.y, centre.z);
    s += fmt::format("f {} {} {} {}\n", base, base + 1, base + 2, base + 3);
    return s;
}

class SessionCamera : public testing::Test {
protected:
    void SetUp() override {
        mDir = fs::temp_directory_path() /
               fmt::format("mvr-camera-{}-{}", ::getpid(),
                           testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(mDir);
        std::ofstream(mDir / "m.mtl") << "newmtl white\nKd 0.8 0.8 0.8\n"
                                      << "newmtl red\nKd 1 0 0\nKa 1 0 0\n"
                                      << "newmtl blue\nKd 0 0 1\nKa 0 0 1\n";
    }
    void TearDown() override { fs::remove_all(mDir); }

    /// Writes the OBJ and renders one view of it with `camera` (and the recipe's fov).
    Image render(const std::string& obj, const CameraRecipe& camera, int w = 160, int h = 120,
                 const std::string& background = "") {
        std::ofstream(mDir / "s.obj") << "mtllib m.mtl\n" << obj;
        RenderRecipe r;
        r.models = {(mDir / "s.obj").string()};
        r.views = 1;
        r.size = fmt::format("{}x{}", w, h);
        r.shading = "flat";
        r.camera = camera;
        r.background = background;
        auto out = renderStill(r, [](const std::string&) {});
        EXPECT_TRUE(out) << out.status().message();
        return out ? out->output.color.at(0) : Image();
    }

    fs::path mDir;
};

/// Pixels whose colour is mostly red (r > 2 (g + b)) / blue, and the red ones' centroid.
struct Marks {
    int red = 0, blue = 0;
    glm::vec2 redCentre{0.0f};
};
Marks marks(const Image& img) {
    Marks m;
    for (int y = 0; y < img.height; ++y) {
        for (int x = 0; x < img.width; ++x) {
            const Rgba8 c = img.at(x, y);
            if (c.r > 60 && c.r > 2 * (c.g + c.b)) {
                ++m.red;
                m.redCentre += glm::vec2(x + 0.5f, y + 0.5f);
            }
            if (c.b > 60 && c.b > 2 * (c.r + c.g)) ++m.blue;
        }
    }
    if (m.red) m.redCentre /= float(m.red);
    return m;
}

// A white cube with a red marker on its +X side and a blue one on its -X side: the default
// framing looks from +Z and sees neither flat-on; --azimuth 90 sees the +X side (red, no blue),
// -90 the -X side (blue, no red).
TEST_F(SessionCamera, AzimuthNinetySeesThePlusXSide) {
    const std::string obj = objBox({-1, -1, -1}, {1, 1, 1}, "white", 1) +
                            objBox({1.0f, -0.3f, -0.3f}, {1.05f, 0.3f, 0.3f}, "red", 9) +
                            objBox({-1.05f, -0.3f, -0.3f}, {-1.0f, 0.3f, 0.3f}, "blue", 17);
    CameraRecipe c;
    c.azimuth = 90.0;
    const Marks plusX = marks(render(obj, c));
    EXPECT_GT(plusX.red, 300);
    EXPECT_EQ(plusX.blue, 0);
    c.azimuth = -90.0;
    const Marks minusX = marks(render(obj, c));
    EXPECT_GT(minusX.blue, 300);
    EXPECT_EQ(minusX.red, 0);
    c.azimuth = 90.0;
    c.elevation = 90.0;  // straight above: neither side face
    const Marks above = marks(render(obj, c));
    EXPECT_EQ(above.red + above.blue, 0);
}

// An eye at (0, 0, 10) looking at the origin with the default 45 degree vertical field of
// view: a small red square around (1.5, 0.5, 0) lands where the pinhole puts it, computed here.
// The same camera as a matrix (row-major world-from-camera: a translation by +10 in z) gives
// the same image, byte for byte.
TEST_F(SessionCamera, AnEyeAndLookAtPutAPointWhereThePinholeDoes) {
    const glm::vec3 mark(1.5f, 0.5f, 0.0f);
    const std::string obj = objBox({-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, -0.4f}, "white", 1) +
                            objSquare(mark, 0.2f, "red", 9);
    const int w = 200, h = 150;
    CameraRecipe c;
    c.position = "0,0,10";
    c.lookAt = "0,0,0";
    const Image eye = render(obj, c, w, h);
    const Marks m = marks(eye);
    ASSERT_GT(m.red, 30);
    const float f = 1.0f / std::tan(glm::radians(22.5f));
    const float ndcX = f / (float(w) / h) * mark.x / 10.0f;
    const float ndcY = f * mark.y / 10.0f;
    EXPECT_NEAR(m.redCentre.x, (ndcX * 0.5f + 0.5f) * w, 0.75f);
    EXPECT_NEAR(m.redCentre.y, (0.5f - ndcY * 0.5f) * h, 0.75f);

    CameraRecipe matrix;
    matrix.matrix = "1 0 0 0  0 1 0 0  0 0 1 10  0 0 0 1";
    const Image viaMatrix = render(obj, matrix, w, h);
    EXPECT_EQ(eye.rgba, viaMatrix.rgba);
    std::ofstream(mDir / "camera.json") << "[[1,0,0,0],[0,1,0,0],[0,0,1,10],[0,0,0,1]]";
    matrix.matrix = (mDir / "camera.json").string();
    EXPECT_EQ(eye.rgba, render(obj, matrix, w, h).rgba);
}

// cameras.json (--write-cameras): for every view of a stereo pair and of a 3x3 grid (off-axis
// shifts in x and y), a red square's centre at a known world position lands at the pixel the
// test computes from the written world_from_camera and intrinsics (OpenCV pinhole), within
// half a pixel of the drawn square's centroid.
TEST_F(SessionCamera, WrittenCamerasProjectAPointWhereItIsDrawn) {
    const glm::vec3 mark(0.4f, 0.3f, 0.2f);
    std::ofstream(mDir / "s.obj") << "mtllib m.mtl\n"
                                  << objBox({-1, -1, -1}, {1, 1, -0.8f}, "white", 1)
                                  << objSquare(mark, 0.12f, "red", 9);
    for (const char* grid : {"", "3x3"}) {
        SCOPED_TRACE(*grid ? grid : "stereo pair");
        RenderRecipe r;
        r.models = {(mDir / "s.obj").string()};
        if (*grid) r.viewGrid = grid;
        r.size = "160x120";
        r.shading = "flat";
        r.separation = 0.05;  // clearly different views
        r.outputs.directory = (mDir / "out").string();
        r.outputs.cameras = true;
        auto out = renderStill(r, [](const std::string&) {});
        ASSERT_TRUE(out) << out.status().message();
        std::ifstream in(mDir / "out" / "cameras.json");
        const nlohmann::json j = nlohmann::json::parse(in);
        ASSERT_EQ(j["views"].size(), out->output.color.size());
        EXPECT_EQ(j["width"], 160);
        for (std::size_t v = 0; v < out->output.color.size(); ++v) {
            const nlohmann::json& cam = j["views"][v];
            glm::mat4 worldFromCamera;
            for (int row = 0; row < 4; ++row)
                for (int col = 0; col < 4; ++col)
                    worldFromCamera[col][row] = cam["world_from_camera"][row][col].get<float>();
            const glm::vec3 p = glm::vec3(glm::inverse(worldFromCamera) * glm::vec4(mark, 1.0f));
            const double X = p.x, Y = -p.y, Z = -p.z;  // OpenCV axes
            const nlohmann::json& k = cam["intrinsics"];
            const double u = k["fx"].get<double>() * X / Z + k["cx"].get<double>();
            const double w = k["fy"].get<double>() * Y / Z + k["cy"].get<double>();
            const Marks m = marks(out->output.color[v]);
            ASSERT_GT(m.red, 20) << "view " << v;
            EXPECT_NEAR(m.redCentre.x - 0.5, u, 0.5) << "view " << v;
            EXPECT_NEAR(m.redCentre.y - 0.5, w, 0.5) << "view " << v;
        }
        if (*grid) {  // the grid's corner views are shifted both ways
            EXPECT_NE(j["views"][0]["intrinsics"]["cy"], j["views"][8]["intrinsics"]["cy"]);
        }
        fs::remove_all(mDir / "out");
    }
}

// A 50 mm lens on a 36 mm sensor: horizontal field of view 2 atan(18 / 50); the vertical
// one follows from the aspect.
TEST_F(SessionCamera, AFocalLengthGivesTheLensFieldOfView) {
    CameraRecipe c;
    c.focalLengthMm = 50.0;
    auto fov = fovFromFocalLength(c, 4.0 / 3.0);
    ASSERT_TRUE(fov && *fov);
    const double halfX = std::atan(18.0 / 50.0);
    EXPECT_NEAR(**fov, 2.0 * glm::degrees(std::atan(std::tan(halfX) * 3.0 / 4.0)), 1e-9);
    RenderRecipe r;
    r.size = "64x48";
    r.camera = c;
    auto p = prepare(r);
    ASSERT_TRUE(p) << p.status().message();
    EXPECT_NEAR(p->rig.camera.fovYDegrees, **fov, 1e-4);
    r.fov = 30.0;
    auto both = prepare(r);
    ASSERT_FALSE(both);
    EXPECT_EQ(both.status().message(), "--focal-length-mm excludes --fov (give one of them)");
}

TEST_F(SessionCamera, TheBackgroundIsTheColourGiven) {
    const std::string obj = objBox({-0.1f, -0.1f, -0.1f}, {0.1f, 0.1f, 0.1f}, "white", 1);
    const Image img = render(obj, {}, 64, 48, "#336699");
    const Rgba8 corner = img.at(0, 0);
    EXPECT_EQ(int(corner.r), 0x33);
    EXPECT_EQ(int(corner.g), 0x66);
    EXPECT_EQ(int(corner.b), 0x99);
    EXPECT_EQ(render(obj, {}, 64, 48, "0.2,0.4,0.6").rgba, img.rgba);
}

TEST(SessionCameraErrors, NameTheOptionAndItsValue) {
    auto message = [](const CameraRecipe& c, const std::string& background = "") {
        RenderRecipe r;
        r.size = "64x48";
        r.camera = c;
        r.background = background;
        auto p = prepare(r);
        EXPECT_FALSE(p);
        EXPECT_EQ(p ? ErrorCode::Internal : p.status().code(), ErrorCode::Usage);
        return p ? std::string() : p.status().message();
    };
    CameraRecipe c;
    c.azimuth = 10.0;
    c.position = "1,2,3";
    EXPECT_NE(message(c).find("the camera is given twice"), std::string::npos);
    c = {};
    c.elevation = 95.0;
    EXPECT_EQ(message(c), "--elevation 95 is out of range (expected -90..90 degrees)");
    c = {};
    c.distance = -1.0;
    EXPECT_EQ(message(c), "--distance -1 is out of range (expected > 0)");
    c = {};
    c.position = "1,2";
    EXPECT_EQ(message(c), "--camera-position 1,2: expected X,Y,Z (three numbers)");
    c = {};
    c.position = "1,nan,2";
    EXPECT_EQ(message(c), "--camera-position 1,nan,2: 'nan' is not a finite number");
    c = {};
    c.lookAt = "0,0,0";
    EXPECT_EQ(message(c), "--look-at / --up need --camera-position");
    c = {};
    c.position = "0,5,0";
    c.lookAt = "0,0,0";  // looking straight down with up +Y
    EXPECT_EQ(message(c), "--up is parallel to the direction the camera looks (give another --up)");
    c = {};
    c.matrix = "1 0 0 0 0 1 0 0 0 0 1 10 1 0 0 1";
    EXPECT_NE(message(c).find("the last row must be 0 0 0 1"), std::string::npos);
    c = {};
    c.focalLengthMm = 0.0;
    EXPECT_EQ(message(c), "--focal-length-mm 0 is out of range (expected > 0)");
    EXPECT_EQ(message({}, "1,1"), "--background 1,1: expected R,G,B in 0..1 or #RRGGBB");
    EXPECT_EQ(message({}, "#12345g"), "--background #12345g: expected #RRGGBB (hex digits)");
}

}  // namespace
}  // namespace mvr::session

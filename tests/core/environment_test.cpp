// Image lighting's once-per-map parts (mvr/core/environment.h) against values computed here:
// the irradiance of a uniform and of a half-lit map (closed forms), the prefiltered levels of a
// uniform map, the split sum's table against a quadrature of the BRDF written out, the map's
// orientation against the sky's; and loadEnvironmentMap on Radiance files this test encodes
// itself (flat and run-length scanlines), OpenEXR written through OpenEXR, a cube cross, and
// the faults, each with its message.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <OpenEXR/ImfRgbaFile.h>
#include <gtest/gtest.h>

#include "mvr/core/environment.h"
#include "mvr/core/stereo_surfaces.h"
#include "mvr/io/scene_io.h"

namespace mvr {
namespace {

constexpr double kPiD = 3.14159265358979323846;

RadianceMap mapOf(int w, int h, const std::function<glm::vec3(glm::vec3)>& radiance) {
    RadianceMap m;
    m.width = w, m.height = h;
    m.texels.resize(std::size_t(w * h));
    for (int j = 0; j < h; ++j) {
        for (int i = 0; i < w; ++i) {
            // The direction through the texel's centre, from the layout's definition (the sky's:
            // u = 0.5 + atan2(x, −z) / 2π, v = 0.5 − asin(y) / π), written out.
            const double lon = ((i + 0.5) / w - 0.5) * 2.0 * kPiD;
            const double lat = (0.5 - (j + 0.5) / h) * kPiD;
            const glm::vec3 d(std::cos(lat) * std::sin(lon), std::sin(lat),
                              -std::cos(lat) * std::cos(lon));
            m.texels[std::size_t(j * w + i)] = radiance(d);
        }
    }
    return m;
}

std::vector<glm::vec3> someNormals() {
    std::vector<glm::vec3> n;
    for (int a = 0; a < 8; ++a) {
        for (int b = -3; b <= 3; ++b) {
            const double lon = a * kPiD / 4 + 0.1, lat = b * kPiD / 7;
            n.emplace_back(std::cos(lat) * std::sin(lon), std::sin(lat),
                           -std::cos(lat) * std::cos(lon));
        }
    }
    return n;
}

TEST(Environment, AUniformMapLightsAWhiteSurfaceWithItsRadianceEverywhere) {
    const glm::vec3 c(0.3f, 1.5f, 4.0f);
    const Environment env = buildEnvironment(mapOf(128, 64, [&](glm::vec3) { return c; }));
    for (const glm::vec3 n : someNormals()) {
        const glm::vec3 e = diffuseLight(env, n);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(e[k], c[k], 2e-3 * c[k]) << k;
        for (const float r : {0.0f, 0.1f, 0.5f, 0.77f, 1.0f}) {
            const glm::vec3 p = prefiltered(env, n, r);
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(p[k], c[k], 1e-4 * c[k]) << r;
        }
    }
    // The levels halve from the largest power of two the map holds.
    EXPECT_EQ(env.levels[0].width, 128);
    EXPECT_EQ(env.levels[0].height, 64);
    EXPECT_EQ(env.levels[5].width, 4);
}

TEST(Environment, AMapLitInItsUpperHalfGivesTheClampedCosinesClosedForm) {
    // Radiance 1 above the horizon, 0 below: irradiance / π at normal n is (1 + n.y) / 2 (the
    // lit solid angle's projected area); second-order SH hold it exactly (the step's bands
    // above 0 are odd, and the clamped cosine has no odd band above 1).
    const Environment env =
        buildEnvironment(mapOf(256, 128, [](glm::vec3 d) { return glm::vec3(d.y > 0 ? 1.0f : 0.0f); }));
    for (const glm::vec3 n : someNormals()) {
        const double want = (1.0 + n.y) / 2.0;
        EXPECT_NEAR(diffuseLight(env, n).x, want, 6e-3) << n.x << " " << n.y << " " << n.z;
    }
    // A scale (--exposure) scales it.
    const Environment twice = buildEnvironment(
        mapOf(256, 128, [](glm::vec3 d) { return glm::vec3(d.y > 0 ? 1.0f : 0.0f); }), 2.0f);
    EXPECT_NEAR(diffuseLight(twice, {0, 1, 0}).x, 2.0, 1.2e-2);
}

TEST(Environment, TheSecondBandIsConvolvedByAQuarter) {
    // Radiance d.y² = 1/3 + (2/3) P2(d.y), P2 = (3y² − 1) / 2: bands 0 and 2 only, so the
    // irradiance / π is 1/3 + (1/4)(2/3) P2(n.y) exactly (Â_2 / π = 1/4).
    const Environment env =
        buildEnvironment(mapOf(256, 128, [](glm::vec3 d) { return glm::vec3(d.y * d.y); }));
    for (const glm::vec3 n : someNormals()) {
        const double want = 1.0 / 3.0 + (1.0 / 6.0) * (3.0 * n.y * n.y - 1.0) / 2.0;
        EXPECT_NEAR(diffuseLight(env, n).x, want, 2e-3) << n.x << " " << n.y << " " << n.z;
    }
}

/// The GGX-prefiltered radiance of `radiance` about unit n (n = v = r, split sum's assumption)
/// by brute force: every direction of a fine grid weighted by D(h) · n·l (the GGX sample
/// density times the n·l weight), D written out.
double prefilteredByQuadrature(const std::function<double(glm::dvec3)>& radiance, glm::dvec3 n,
                               double roughness) {
    const double alpha = std::max(roughness * roughness, 1e-3), a2 = alpha * alpha;
    double sum = 0.0, weight = 0.0;
    const int nt = 720, np = 1440;
    for (int t = 0; t < nt; ++t) {
        const double lat = (0.5 - (t + 0.5) / nt) * kPiD;
        for (int p = 0; p < np; ++p) {
            const double lon = ((p + 0.5) / np - 0.5) * 2.0 * kPiD;
            const glm::dvec3 l(std::cos(lat) * std::sin(lon), std::sin(lat),
                               -std::cos(lat) * std::cos(lon));
            const double nl = glm::dot(n, l);
            if (nl <= 0.0) continue;
            const double nh = glm::dot(n, glm::normalize(n + l));
            const double d = a2 / (kPiD * std::pow(nh * nh * (a2 - 1.0) + 1.0, 2.0));
            const double w = d * nl * std::cos(lat);  // × the grid cell's solid angle
            sum += radiance(l) * w;
            weight += w;
        }
    }
    return sum / weight;
}

TEST(Environment, ThePrefilteredLevelsAreTheGgxLobesAverage) {
    auto radiance = [](glm::dvec3 d) { return 1.0 + d.x + 0.5 * d.y * d.y; };
    const Environment env = buildEnvironment(
        mapOf(512, 256, [&](glm::vec3 d) { return glm::vec3(float(radiance(glm::dvec3(d)))); }));
    for (const double r : {0.4, 0.6, 1.0}) {
        for (const glm::vec3 n : {glm::vec3(1, 0, 0), glm::vec3(-0.6f, 0.0f, 0.8f),
                                  glm::vec3(0.0f, 0.6f, -0.8f), glm::vec3(0.48f, -0.6f, 0.64f)}) {
            const double want = prefilteredByQuadrature(radiance, glm::dvec3(n), r);
            // 3 %: the roughest level is 16 × 8 texels, read bilinearly between them.
            EXPECT_NEAR(prefiltered(env, n, float(r)).x, want, 0.03 * want)
                << "roughness " << r << " n " << n.x << "," << n.y << "," << n.z;
        }
    }
    // The roughest lobe is the cosine-weighted mean: 1 + (2/3) n.x for the linear part.
    EXPECT_NEAR(prefilteredByQuadrature([](glm::dvec3 d) { return 1.0 + d.x; },
                                        glm::dvec3(1, 0, 0), 1.0),
                1.0 + 2.0 / 3.0, 1e-3);
}

/// ∫ f · cos over the hemisphere of glTF's specular BRDF with F0 = 1 − Fc (A) and Fc (B)
/// weights, by a midpoint rule in (θ, φ) about n: D, V and Schlick's term written out.
glm::dvec2 splitSumByQuadrature(double nv, double roughness) {
    const double alpha = std::max(roughness * roughness, 1e-3), a2 = alpha * alpha;
    const glm::dvec3 v(std::sqrt(1.0 - nv * nv), 0.0, nv);
    const int nt = 1500, np = 600;
    glm::dvec2 sum(0.0);
    for (int t = 0; t < nt; ++t) {
        const double theta = (t + 0.5) / nt * (kPiD / 2);
        for (int p = 0; p < np; ++p) {
            const double phi = (p + 0.5) / np * 2.0 * kPiD;
            const glm::dvec3 l(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                               std::cos(theta));
            const glm::dvec3 h = glm::normalize(l + v);
            const double nl = l.z, nh = h.z, vh = glm::dot(v, h);
            const double d = a2 / (kPiD * std::pow(nh * nh * (a2 - 1.0) + 1.0, 2.0));
            const double vis = 1.0 / ((nl + std::sqrt(a2 + (1 - a2) * nl * nl)) *
                                      (nv + std::sqrt(a2 + (1 - a2) * nv * nv)));
            const double fc = std::pow(1.0 - vh, 5.0);
            const double dOmega = std::sin(theta) * (kPiD / 2 / nt) * (2 * kPiD / np);
            sum += glm::dvec2(1.0 - fc, fc) * (d * vis * nl * dOmega);
        }
    }
    return sum;
}

TEST(Environment, TheSplitSumTableIsTheBrdfsIntegral) {
    const auto& table = splitSumTable();
    for (const int j : {12, 20, 31}) {      // roughness 0.39, 0.64, 0.98
        for (const int i : {6, 16, 31}) {   // n·v 0.20, 0.52, 0.98
            const double r = (j + 0.5) / kBrdfSize, nv = (i + 0.5) / kBrdfSize;
            const glm::dvec2 want = splitSumByQuadrature(nv, r);
            const glm::vec2 got = table[std::size_t(j * kBrdfSize + i)];
            EXPECT_NEAR(got.x, want.x, 0.02) << "A at r " << r << " nv " << nv;
            EXPECT_NEAR(got.y, want.y, 0.01) << "B at r " << r << " nv " << nv;
            // The lookup at a texel's centre is that texel.
            EXPECT_EQ(splitSum(float(nv), float(r)), got);
        }
    }
    // A mirror seen head on reflects everything: A + B = 1.
    const glm::vec2 mirror = splitSum(1.0f, 0.0f);
    EXPECT_NEAR(mirror.x + mirror.y, 1.0f, 0.02f);
}

TEST(Environment, ItsMapIsTheSkysWayRound) {
    // An 8-bit sky map and the same texels as radiance (byte / 255): level 0 (the map as it
    // is, 64 × 32) looked up in a direction is the sky's colour in that direction.
    Image image(64, 32, Rgba8{0, 0, 0, 255});
    RadianceMap map;
    map.width = 64, map.height = 32;
    map.texels.resize(64 * 32);
    for (int j = 0; j < 32; ++j) {
        for (int i = 0; i < 64; ++i) {
            const Rgba8 c{std::uint8_t(i * 4), std::uint8_t(j * 8), std::uint8_t((i * j) % 256), 255};
            std::memcpy(image.rgba.data() + (std::size_t(j) * 64 + std::size_t(i)) * 4, &c, 4);
            map.texels[std::size_t(j * 64 + i)] = glm::vec3(c.r, c.g, c.b) / 255.0f;
        }
    }
    Sky sky;
    sky.kind = Sky::Kind::Equirect;
    sky.image = image;
    const Environment env = buildEnvironment(map);
    ASSERT_EQ(env.levels[0].width, 64);
    for (const glm::vec3 d : {glm::vec3(0, 0, -1), glm::vec3(0.6f, 0.3f, 0.1f),
                              glm::vec3(-0.2f, -0.7f, 0.4f), glm::vec3(0.1f, 0.2f, 0.9f)}) {
        const glm::vec3 want = skyColor(sky, d), got = prefiltered(env, glm::normalize(d), 0.0f);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], want[k], 2e-3) << d.x << " " << k;
    }
    // Straight ahead (−Z) is the map's centre column; +X is a quarter to its right.
    EXPECT_NEAR(equirectUv({0, 0, -1}).x, 0.5f, 1e-6f);
    EXPECT_NEAR(equirectUv({1, 0, 0}).x, 0.75f, 1e-6f);
    EXPECT_NEAR(equirectUv({0, 1, 0}).y, 0.0f, 1e-6f);
}

// ---- loadEnvironmentMap ----------------------------------------------------------------------

std::filesystem::path tempDir() {
    const auto d = std::filesystem::temp_directory_path() /
                   ("mvr_env_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
}

void writeBytes(const std::filesystem::path& p, const std::string& bytes) {
    std::ofstream(p, std::ios::binary) << bytes;
}

/// A float as RGBE's shared exponent (Ward's float2rgbe): m · 2^(e − 128 − 8).
std::string rgbe(float r, float g, float b) {
    const float v = std::max({r, g, b});
    if (v < 1e-32f) return std::string(4, '\0');
    int e = 0;
    const float m = std::frexp(v, &e) * 256.0f / v;
    return {char(std::uint8_t(r * m)), char(std::uint8_t(g * m)), char(std::uint8_t(b * m)),
            char(std::uint8_t(e + 128))};
}

std::string radianceHeader(int w, int h) {
    return "#?RADIANCE\n# written by mvr's test\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=1.0\n\n-Y " +
           std::to_string(h) + " +X " + std::to_string(w) + "\n";
}

/// A scanline run-length encoded per channel the way Radiance writes it: runs of > 2 equal
/// bytes as (128 + n, value), the rest as (n, literals).
std::string rleScanline(const std::vector<std::string>& texels) {
    const int w = int(texels.size());
    std::string out{char(2), char(2), char(w >> 8), char(w & 0xff)};
    for (int c = 0; c < 4; ++c) {
        int x = 0;
        while (x < w) {
            int run = 1;
            while (x + run < w && run < 127 && texels[x + run][c] == texels[x][c]) ++run;
            if (run > 2) {
                out += char(128 + run);
                out += texels[x][c];
                x += run;
            } else {
                int n = 0;
                std::string lit;
                while (x + n < w && n < 128) {
                    lit += texels[x + n][c];
                    ++n;
                    if (x + n + 2 < w && texels[x + n][c] == texels[x + n + 1][c] &&
                        texels[x + n][c] == texels[x + n + 2][c])
                        break;
                }
                out += char(n);
                out += lit;
                x += n;
            }
        }
    }
    return out;
}

float expected(float f) {  // what RGBE keeps of f (8 bits of mantissa)
    const std::string e = rgbe(f, f, f);
    return float(std::uint8_t(e[0])) * std::ldexp(1.0f, int(std::uint8_t(e[3])) - 136);
}

TEST(EnvironmentFiles, RadianceFlatAndRunLengthScanlinesDecode) {
    const auto dir = tempDir();
    const int w = 16, h = 8;
    auto value = [](int x, int y) { return glm::vec3(0.1f * x, 2.0f + y, (x < 8 ? 50.0f : 0.25f)); };
    std::string flat = radianceHeader(w, h), rle = radianceHeader(w, h);
    for (int y = 0; y < h; ++y) {
        std::vector<std::string> row;
        for (int x = 0; x < w; ++x) {
            const glm::vec3 v = value(x, y);
            row.push_back(rgbe(v.x, v.y, v.z));
            flat += row.back();
        }
        rle += rleScanline(row);
    }
    writeBytes(dir / "flat.hdr", flat);
    writeBytes(dir / "rle.pic", rle);  // not told apart by the name
    for (const char* name : {"flat.hdr", "rle.pic"}) {
        auto map = loadEnvironmentMap((dir / name).string());
        ASSERT_TRUE(map) << map.status().message();
        ASSERT_EQ(map->width, w);
        ASSERT_EQ(map->height, h);
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x) {
                const glm::vec3 got = map->texels[std::size_t(y * w + x)], want = value(x, y);
                const float scale = std::max({want.x, want.y, want.z});
                for (int k = 0; k < 3; ++k)
                    EXPECT_NEAR(got[k], want[k], scale / 128.0f) << name << " " << x << "," << y;
            }
        }
        EXPECT_EQ(map->texels[0].y, expected(2.0f));
    }
}

TEST(EnvironmentFiles, OpenExrAndACubeCrossLoad) {
    const auto dir = tempDir();
    {  // 8 × 4 half-float RGBA, as Blender and Poly Haven write them
        std::vector<Imf::Rgba> px(32);
        for (int k = 0; k < 32; ++k) px[std::size_t(k)] = Imf::Rgba(half(k * 0.5f), half(3.0f), half(0.0f), half(1.0f));
        Imf::RgbaOutputFile out((dir / "env.exr").c_str(), 8, 4, Imf::WRITE_RGBA);
        out.setFrameBuffer(px.data(), 1, 8);
        out.writePixels(4);
    }
    auto exr = loadEnvironmentMap((dir / "env.exr").string());
    ASSERT_TRUE(exr) << exr.status().message();
    EXPECT_EQ(exr->width, 8);
    EXPECT_EQ(exr->texels[13].x, 6.5f);
    EXPECT_EQ(exr->texels[13].y, 3.0f);

    // A cube cross of 4 × 3 faces of side 4, each face one colour: the map it becomes shows
    // each face's colour in the face's direction.
    const int s = 4;
    std::string hdr = radianceHeader(4 * s, 3 * s);
    auto faceColour = [](int col, int row) { return glm::vec3(col + 1, row + 1, 0.5f); };
    for (int y = 0; y < 3 * s; ++y)
        for (int x = 0; x < 4 * s; ++x) {
            const glm::vec3 c = faceColour(x / s, y / s);
            hdr += rgbe(c.x, c.y, c.z);
        }
    writeBytes(dir / "cross.hdr", hdr);
    auto cross = loadEnvironmentMap((dir / "cross.hdr").string());
    ASSERT_TRUE(cross) << cross.status().message();
    ASSERT_EQ(cross->width, 4 * s);
    ASSERT_EQ(cross->height, 2 * s);
    const Environment env = buildEnvironment(*cross);
    // The cross's layout (stereo_surfaces.h): +Y top of −Z, then −X, −Z, +X, +Z, then −Y.
    const struct {
        glm::vec3 d;
        int col, row;
    } faces[] = {{{0, 0, -1}, 1, 1}, {{1, 0, 0}, 2, 1}, {{-1, 0, 0}, 0, 1},
                 {{0, 0, 1}, 3, 1},  {{0, 1, 0}, 1, 0}, {{0, -1, 0}, 1, 2}};
    for (const auto& f : faces) {
        const glm::vec3 got = prefiltered(env, f.d, 0.0f), want = faceColour(f.col, f.row);
        EXPECT_NEAR(got.x, want.x, 0.05f) << f.d.x << f.d.y << f.d.z;
        EXPECT_NEAR(got.y, want.y, 0.05f) << f.d.x << f.d.y << f.d.z;
    }
}

TEST(EnvironmentFiles, TheBrightestTexelsAreKeptFinite) {
    // RGBE's largest exponent (255: about 1.7e38 a channel) reads kMaxRadiance, and a map of
    // it scaled by --exposure's 2^64 builds finite levels and SH.
    const auto dir = tempDir();
    std::string hdr = radianceHeader(8, 4);
    for (int k = 0; k < 32; ++k) hdr += k == 5 ? std::string{char(255), char(255), char(255), char(255)} : rgbe(1, 1, 1);
    writeBytes(dir / "sun.hdr", hdr);
    auto map = loadEnvironmentMap((dir / "sun.hdr").string());
    ASSERT_TRUE(map) << map.status().message();
    EXPECT_EQ(map->texels[5].x, kMaxRadiance);
    const Environment env = buildEnvironment(*map, std::exp2(64.0f));
    for (const auto& level : env.levels)
        for (const glm::vec4& t : level.texels) ASSERT_TRUE(std::isfinite(t.x)) << level.width;
    EXPECT_TRUE(std::isfinite(diffuseLight(env, {0, 1, 0}).x));
}

TEST(EnvironmentFiles, FaultsAreOneLineNamingTheFileAndThePlace) {
    const auto dir = tempDir();
    auto error = [](const std::filesystem::path& p) {
        auto m = loadEnvironmentMap(p.string());
        return m ? std::string("(loaded)") : m.status().message();
    };
    EXPECT_EQ(error(dir / "none.hdr"),
              "--environment '" + (dir / "none.hdr").string() + "': file not found");
    std::string good = radianceHeader(8, 4);
    for (int k = 0; k < 32; ++k) good += rgbe(1, 1, 1);
    writeBytes(dir / "short.hdr", good.substr(0, good.size() - 40));
    EXPECT_NE(error(dir / "short.hdr").find("scanline 2 of 4: the file ends early"),
              std::string::npos)
        << error(dir / "short.hdr");
    const std::string padding(64, '\1');  // bytes enough for 4 scanlines, so the rows are read
    std::string runaway =
        radianceHeader(8, 4) + std::string{2, 2, 0, 8} + char(128 + 100) + 'x' + padding;
    writeBytes(dir / "runaway.hdr", runaway);
    EXPECT_NE(error(dir / "runaway.hdr").find("scanline 0: a run goes past the row's end"),
              std::string::npos)
        << error(dir / "runaway.hdr");
    // A zero-length literal run would never advance (stb_image's hang): refused.
    std::string stuck = radianceHeader(8, 4) + std::string{2, 2, 0, 8} + std::string(1, '\0') + padding;
    writeBytes(dir / "stuck.hdr", stuck);
    EXPECT_NE(error(dir / "stuck.hdr").find("scanline 0: a run of length 0"), std::string::npos)
        << error(dir / "stuck.hdr");
    writeBytes(dir / "xyze.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 4 +X 8\n");
    EXPECT_NE(error(dir / "xyze.hdr").find("only FORMAT=32-bit_rle_rgbe is read"),
              std::string::npos);
    writeBytes(dir / "flip.hdr", "#?RADIANCE\n\n+Y 4 +X 8\n" + std::string(128, '\1'));
    EXPECT_NE(error(dir / "flip.hdr").find("resolution '+Y 4 +X 8' is not '-Y H +X W'"),
              std::string::npos);
    writeBytes(dir / "huge.hdr", "#?RADIANCE\n\n-Y 100000 +X 200000\n");
    EXPECT_NE(error(dir / "huge.hdr").find("200000x100000 texels: out of range"), std::string::npos);
    std::string wide = radianceHeader(12, 4);
    for (int k = 0; k < 48; ++k) wide += rgbe(1, 1, 1);
    writeBytes(dir / "wide.hdr", wide);
    EXPECT_NE(error(dir / "wide.hdr").find("12x4 is neither an equirectangular map"),
              std::string::npos);
    writeBytes(dir / "text.hdr", "hello");
    EXPECT_EQ(error(dir / "text.hdr"), "--environment '" + (dir / "text.hdr").string() +
                                           "': not a Radiance (.hdr), OpenEXR, PNG or JPEG image");
    writeBytes(dir / "broken.exr", std::string("\x76\x2f\x31\x01garbage", 11));
    EXPECT_NE(error(dir / "broken.exr").find("not a readable OpenEXR file"), std::string::npos);
    {  // a NaN texel, as a broken EXR export writes it
        std::vector<Imf::Rgba> px(8, Imf::Rgba(half(1.0f), half(1.0f), half(1.0f), half(1.0f)));
        px[3].g = half(std::numeric_limits<float>::quiet_NaN());
        Imf::RgbaOutputFile out((dir / "nan.exr").c_str(), 4, 2, Imf::WRITE_RGBA);
        out.setFrameBuffer(px.data(), 1, 4);
        out.writePixels(2);
    }
    EXPECT_NE(error(dir / "nan.exr").find("texel (3, 0) is not finite"), std::string::npos)
        << error(dir / "nan.exr");
    // Windows line ends in the header, blanks around the size: read.
    std::string crlf = "#?RADIANCE\r\nFORMAT=32-bit_rle_rgbe\r\n\r\n-Y 4 +X 8 \n";
    for (int k = 0; k < 32; ++k) crlf += rgbe(1, 1, 1);
    writeBytes(dir / "crlf.hdr", crlf);
    EXPECT_EQ(error(dir / "crlf.hdr"), "(loaded)");
    // A header that claims more texels than its bytes could hold is refused before allocating.
    writeBytes(dir / "claims.hdr", "#?RADIANCE\n\n-Y 4096 +X 8192\n" + std::string(100, '\2'));
    EXPECT_NE(error(dir / "claims.hdr").find("cannot hold 4096 scanlines of 8192 texels"),
              std::string::npos)
        << error(dir / "claims.hdr");
    std::filesystem::create_directories(dir / "folder.hdr");
    EXPECT_NE(error(dir / "folder.hdr").find("not a regular file (a directory)"), std::string::npos);
}

}  // namespace
}  // namespace mvr

// The village scene of adelson1991's simple renderer test, its lighting and camera.
#include <algorithm>
#include <cmath>

#include "count.h"
#include "mvr/adelson/adelson.h"

namespace mvr::adelson {

using detail::Count;
using detail::dispatch;

namespace {

Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec3 operator*(Vec3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec3 cross(Vec3 a, Vec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

struct Builder {
    std::vector<Polygon3> polys;
    /// Adds a polygon, its vertex order flipped when needed so that its normal points away
    /// from `inside`.
    void add(std::vector<Vec3> v, Rgb albedo, Vec3 inside) {
        Vec3 c{};
        for (const Vec3& p : v) c = c + p;
        c = c * (1.0 / double(v.size()));
        if (dot(cross(v[1] - v[0], v[2] - v[0]), c - inside) < 0.0)
            std::reverse(v.begin(), v.end());
        Polygon3 p;
        p.v = std::move(v);
        p.albedo = albedo;
        p.color.assign(p.v.size(), albedo);
        p.id = std::uint32_t(polys.size());
        polys.push_back(std::move(p));
    }
    /// A rectangle o + [0,1]·u + [0,1]·v cut into nu × nv quads.
    void grid(Vec3 o, Vec3 u, Vec3 v, int nu, int nv, Rgb albedo, Vec3 inside) {
        for (int j = 0; j < nv; ++j) {
            for (int i = 0; i < nu; ++i) {
                const Vec3 a = o + u * (double(i) / nu) + v * (double(j) / nv);
                const Vec3 du = u * (1.0 / nu), dv = v * (1.0 / nv);
                add({a, a + du, a + du + dv, a + dv}, albedo, inside);
            }
        }
    }
};

}  // namespace

PlaneEq planeOf(const Polygon3& p) {
    Vec3 n = cross(p.v[1] - p.v[0], p.v[2] - p.v[0]);
    const double len = std::sqrt(dot(n, n));
    n = n * (len > 0.0 ? 1.0 / len : 0.0);
    return {n.x, n.y, n.z, -dot(n, p.v[0])};
}

std::vector<Polygon3> makeVillage(int buildings) {
    buildings = std::clamp(buildings, 1, 8);
    Builder b;
    const double groundY = -1.5;
    b.grid({-8.0, groundY, 1.0}, {16.0, 0, 0}, {0, 0, 14.0}, 4, 4, {0.35f, 0.55f, 0.25f},
           {0.0, groundY - 1.0, 8.0});
    const double xs[4] = {-4.5, -1.5, 1.5, 4.5};
    const double zs[2] = {5.0, 9.0};
    const Rgb walls[4] = {
        {0.85f, 0.75f, 0.6f}, {0.8f, 0.8f, 0.78f}, {0.9f, 0.65f, 0.5f}, {0.7f, 0.72f, 0.8f}};
    for (int k = 0; k < buildings; ++k) {
        const double cx = xs[k % 4] + (k / 4) * 0.6, cz = zs[k / 4];
        const double w = 1.0, h = 1.5, ridge = 0.9, top = groundY + h;
        const Vec3 center{cx, groundY + h * 0.5, cz};
        const Rgb wall = walls[k % 4], roof{0.6f, 0.2f, 0.15f}, glass{0.2f, 0.3f, 0.45f},
                  door{0.4f, 0.25f, 0.1f}, brick{0.5f, 0.3f, 0.25f};
        // walls: front (−z, towards the viewer), back, two sides
        b.grid({cx - w, groundY, cz - w}, {2 * w, 0, 0}, {0, h, 0}, 6, 4, wall, center);
        b.grid({cx - w, groundY, cz + w}, {2 * w, 0, 0}, {0, h, 0}, 6, 4, wall, center);
        b.grid({cx - w, groundY, cz - w}, {0, 0, 2 * w}, {0, h, 0}, 5, 4, wall, center);
        b.grid({cx + w, groundY, cz - w}, {0, 0, 2 * w}, {0, h, 0}, 5, 4, wall, center);
        // roof slopes (ridge along x) and gables
        const Vec3 roofIn{cx, top, cz};
        b.grid({cx - w, top, cz - w}, {2 * w, 0, 0}, {0, ridge, w}, 6, 3, roof, roofIn);
        b.grid({cx - w, top, cz + w}, {2 * w, 0, 0}, {0, ridge, -w}, 6, 3, roof, roofIn);
        b.add({{cx - w, top, cz - w}, {cx - w, top, cz + w}, {cx - w, top + ridge, cz}}, wall,
              roofIn);
        b.add({{cx + w, top, cz - w}, {cx + w, top, cz + w}, {cx + w, top + ridge, cz}}, wall,
              roofIn);
        // windows (0.02 in front of the walls) and the door
        const double off = 0.02;
        for (int i = 0; i < 3; ++i) {
            const double x0 = cx - 0.8 + i * 0.6;
            for (const double zf : {cz - w - off, cz + w + off}) {
                b.add({{x0, top - 0.7, zf},
                       {x0 + 0.3, top - 0.7, zf},
                       {x0 + 0.3, top - 0.35, zf},
                       {x0, top - 0.35, zf}},
                      glass, center);
            }
        }
        for (const double xf : {cx - w - off, cx + w + off}) {
            b.add({{xf, top - 0.7, cz - 0.15},
                   {xf, top - 0.7, cz + 0.15},
                   {xf, top - 0.35, cz + 0.15},
                   {xf, top - 0.35, cz - 0.15}},
                  glass, center);
        }
        b.add({{cx - 0.15, groundY, cz - w - off},
               {cx + 0.2, groundY, cz - w - off},
               {cx + 0.2, groundY + 0.7, cz - w - off},
               {cx - 0.15, groundY + 0.7, cz - w - off}},
              door, center);
        // chimney: four sides and a top, standing in the back slope
        const double chx = cx + 0.5, chz = cz + 0.45, c0 = top + 0.3, c1 = top + 1.2, s = 0.1;
        const Vec3 chIn{chx, (c0 + c1) * 0.5, chz};
        b.grid({chx - s, c0, chz - s}, {2 * s, 0, 0}, {0, c1 - c0, 0}, 1, 1, brick, chIn);
        b.grid({chx - s, c0, chz + s}, {2 * s, 0, 0}, {0, c1 - c0, 0}, 1, 1, brick, chIn);
        b.grid({chx - s, c0, chz - s}, {0, 0, 2 * s}, {0, c1 - c0, 0}, 1, 1, brick, chIn);
        b.grid({chx + s, c0, chz - s}, {0, 0, 2 * s}, {0, c1 - c0, 0}, 1, 1, brick, chIn);
        b.grid({chx - s, c1, chz - s}, {2 * s, 0, 0}, {0, 0, 2 * s}, 1, 1, brick, {chx, c0, chz});
    }
    return std::move(b.polys);
}

void shadeVertices(std::vector<Polygon3>& polys, OpCounts* ops) {
    const Vec3 light{-6.0, 10.0, -2.0};
    const double ambient = 0.2, kd = 0.9, atten = 0.03;
    dispatch(ops, [&]<bool On>() {
        Count<On> n;
        for (Polygon3& p : polys) {
            const Vec3 e1 = p.v[1] - p.v[0], e2 = p.v[2] - p.v[0];
            Vec3 nrm = cross(e1, e2);
            nrm = nrm * (1.0 / std::sqrt(dot(nrm, nrm)));
            n.add(6 + 3 + 2), n.mul(6 + 3 + 3 + 1);
            p.color.resize(p.v.size());
            for (std::size_t i = 0; i < p.v.size(); ++i) {
                const Vec3 l = light - p.v[i];
                const double dist = std::sqrt(dot(l, l));
                const double lambert = std::max(0.0, dot(nrm, l) / dist);
                const double k = ambient + kd * lambert / (1.0 + atten * dist);
                p.color[i] = {float(p.albedo.r * k), float(p.albedo.g * k), float(p.albedo.b * k)};
                n.add(3 + 2 + 2 + 2), n.mul(3 + 1 + 3 + 1 + 3 + 3), n.cmp();
            }
        }
        n.flush(ops);
    });
}

StereoCamera villageCamera(int width, int height) {
    StereoCamera cam;
    cam.d = 2.0;
    cam.e = 0.2;
    cam.width = width;
    cam.height = height;
    cam.scale = 160.0 * width / 640.0;
    return cam;
}

}  // namespace mvr::adelson

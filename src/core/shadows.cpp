#include "mvr/core/shadows.h"

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include "mvr/core/render.h"

namespace mvr {

std::vector<int> shadowCasters(const Scene& scene) {
    std::vector<int> out;
    const int n = std::min(int(scene.lights.size()), kMaxLights);
    for (int k = 0; k < n; ++k) {
        const Light& l = scene.lights[std::size_t(k)];
        if (l.castsShadow && l.type != LightType::Point) out.push_back(k);
    }
    if (!out.empty()) return out;
    for (int k = 0; k < n; ++k) {
        const Light& l = scene.lights[std::size_t(k)];
        if ((k == 0 && l.type == LightType::Directional) || l.type == LightType::Spot) {
            out.push_back(k);
        }
    }
    return out;
}

namespace {

std::array<glm::vec3, 8> boxCorners(const Bounds& b) {
    std::array<glm::vec3, 8> c;
    for (int i = 0; i < 8; ++i) {
        c[std::size_t(i)] = glm::vec3(i & 1 ? b.max.x : b.min.x, i & 2 ? b.max.y : b.min.y,
                                      i & 4 ? b.max.z : b.min.z);
    }
    return c;
}

glm::vec3 upFor(const glm::vec3& dir) {
    return std::fabs(dir.y) > 0.9f ? glm::vec3(0.0f, 0.0f, -1.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
}

}  // namespace

ShadowMap makeShadowMapView(const Light& light, int lightIndex, const Bounds& bounds, int size) {
    ShadowMap m;
    m.light = lightIndex;
    m.size = size;
    const glm::vec3 center = bounds.center();
    const float radius = std::max(bounds.radius(), 1e-3f);
    const auto corners = boxCorners(bounds);
    const glm::vec3 toward = glm::normalize(light.towardLight);
    if (light.type == LightType::Spot) {
        const glm::vec3 axis = -toward;  // from the light into the scene
        float far = 0.0f;
        for (const glm::vec3& c : corners) far = std::max(far, glm::length(c - light.position));
        far = std::max(far * 1.01f, 1e-2f);
        m.near = far / 200.0f;
        m.far = far;
        const float half = std::clamp(std::acos(std::clamp(light.outerConeCos, -1.0f, 1.0f)),
                                      glm::radians(0.5f), glm::radians(85.0f));
        m.perspective = true;
        m.view.viewFromWorld = glm::lookAt(light.position, light.position + axis, upFor(axis));
        m.view.clipFromView = glm::perspective(2.0f * half, 1.0f, m.near, m.far);
        m.texelWorld = 2.0f * std::tan(half) / float(size);
    } else {
        // Orthographic along the light, fitted to the bounds' corners in light space, with
        // square texels (the larger extent, centred).
        const glm::vec3 eye = center + toward * (2.0f * radius);
        m.view.viewFromWorld = glm::lookAt(eye, center, upFor(-toward));
        glm::vec3 lo(1e30f), hi(-1e30f);
        for (const glm::vec3& c : corners) {
            const glm::vec3 v = glm::vec3(m.view.viewFromWorld * glm::vec4(c, 1.0f));
            lo = glm::min(lo, v);
            hi = glm::max(hi, v);
        }
        const float extent = std::max(hi.x - lo.x, hi.y - lo.y) * 1.02f + 1e-4f;
        const float cx = 0.5f * (lo.x + hi.x), cy = 0.5f * (lo.y + hi.y);
        const float margin = 0.01f * radius + 1e-4f;
        m.near = std::max(-hi.z - margin, 1e-4f);
        m.far = -lo.z + margin;
        m.view.clipFromView = glm::ortho(cx - 0.5f * extent, cx + 0.5f * extent, cy - 0.5f * extent,
                                         cy + 0.5f * extent, m.near, m.far);
        m.texelWorld = extent / float(size);
    }
    m.view.eyeWorld = glm::vec3(glm::inverse(m.view.viewFromWorld)[3]);
    m.clipFromWorld = m.view.clipFromWorld();
    return m;
}

void setShadowDepth(ShadowMap& map, std::span<const float> depth) {
    const int s = map.size;
    map.depth.assign(std::size_t(s) * std::size_t(s), map.far);
    const float n = map.near, f = map.far;
    for (int y = 0; y < s; ++y) {
        const float* row = depth.data() + std::size_t(s - 1 - y) * std::size_t(s);
        float* out = map.depth.data() + std::size_t(y) * std::size_t(s);
        for (int x = 0; x < s; ++x) {
            const float d = row[x];
            out[x] = map.perspective ? (2.0f * n * f) / ((f + n) - (2.0f * d - 1.0f) * (f - n))
                                     : n + d * (f - n);
        }
    }
}

Result<Rig> shadowRig(std::span<const ShadowMap> maps) {
    std::vector<View> views;
    for (const ShadowMap& m : maps) views.push_back(m.view);
    if (views.empty()) return usageError("shadow pass: no shadow-casting light");
    Camera cam;
    cam.position = maps[0].view.eyeWorld;
    const glm::mat4 worldFromView = glm::inverse(maps[0].view.viewFromWorld);
    cam.target = cam.position - glm::vec3(worldFromView[2]);
    cam.up = glm::vec3(worldFromView[1]);
    cam.aspect = 1.0f;
    cam.near = maps[0].near;
    cam.far = maps[0].far;
    return makeListRig(cam, std::move(views));
}

RenderSettings shadowPassSettings(int size) {
    RenderSettings s;
    s.width = s.height = size;
    s.shading = Shading::Flat;
    s.cullBackFaces = false;
    s.wireframe = false;
    s.shadows = false;
    return s;
}

Result<ShadowSet> renderShadowSet(Backend& backend, const Scene& scene, int size,
                                  const std::string& method, bool onePass) {
    ShadowSet set;
    const std::vector<int> casters = shadowCasters(scene);
    if (casters.empty()) return set;
    if (size < 16 || size > 8192) {
        return usageError(
            fmt::format("shadow map size {} is out of range (expected 16..8192)", size));
    }
    const Bounds bounds = scene.bounds();
    if (bounds.empty()) return set;
    for (int k : casters) {
        set.mapOfLight[std::size_t(k)] = int(set.maps.size());
        set.maps.push_back(makeShadowMapView(scene.lights[std::size_t(k)], k, bounds, size));
    }
    const RenderSettings settings = shadowPassSettings(size);
    auto fill = [&](std::span<ShadowMap> maps) -> Status {
        Result<Rig> rig = shadowRig(maps);
        if (!rig) return rig.status();
        Result<RenderOutput> out = backend.render(scene, *rig, settings, method);
        if (!out) return out.status();
        if (out->depth.size() != maps.size()) {
            return usageError(
                fmt::format("--shadows: {} method '{}' returns no depth images for the shadow pass",
                            backend.name(), out->method));
        }
        for (std::size_t i = 0; i < maps.size(); ++i) setShadowDepth(maps[i], out->depth[i].depth);
        return {};
    };
    if (onePass) {
        if (Status s = fill(set.maps); !s) return s;
    } else {
        for (ShadowMap& m : set.maps) {
            if (Status s = fill(std::span<ShadowMap>(&m, 1)); !s) return s;
        }
    }
    return set;
}

}  // namespace mvr

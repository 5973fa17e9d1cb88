#include "mvr/core/animation.h"

#include <algorithm>
#include <cmath>

#include <fmt/core.h>
#include <glm/gtc/matrix_transform.hpp>

#include "mvr/core/screen_rig.h"

namespace mvr {

Camera orbitCamera(const Camera& camera, const glm::vec3& centre, double degrees) {
    glm::vec3 axis = camera.up;
    if (glm::length(axis) <= 0.0f || !std::isfinite(glm::length(axis))) axis = {0, 1, 0};
    axis = glm::normalize(axis);
    const glm::mat4 turn = glm::rotate(glm::mat4(1.0f), float(glm::radians(degrees)), axis);
    Camera out = camera;
    out.position = centre + glm::vec3(turn * glm::vec4(camera.position - centre, 0.0f));
    out.target = centre + glm::vec3(turn * glm::vec4(camera.target - centre, 0.0f));
    return out;
}

double orbitDegrees(double degrees, int frame, int frames) {
    return frames > 0 ? degrees * double(frame) / double(frames) : 0.0;
}

namespace {
bool finite3(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
}  // namespace

Status validateCameraPath(const CameraPath& path) {
    if (path.keys.empty()) return usageError("camera path: no keys");
    for (std::size_t i = 0; i < path.keys.size(); ++i) {
        const CameraKey& k = path.keys[i];
        if (!std::isfinite(k.time) || k.time < 0.0) {
            return usageError(
                fmt::format("camera path: key {}: time {} is not a finite "
                            "number >= 0",
                            i, k.time));
        }
        if (i > 0 && k.time <= path.keys[i - 1].time) {
            return usageError(fmt::format(
                "camera path: key {}: time {} does not follow key {}'s {} (times must increase)", i,
                k.time, i - 1, path.keys[i - 1].time));
        }
        if (!finite3(k.position) || !finite3(k.target)) {
            return usageError(fmt::format("camera path: key {}: non-finite position or target", i));
        }
        if (glm::length(k.position - k.target) <= 0.0f) {
            return usageError(fmt::format("camera path: key {}: position equals target", i));
        }
        if (k.fovYDegrees && !(*k.fovYDegrees > 0.0f && *k.fovYDegrees < 180.0f)) {
            return usageError(
                fmt::format("camera path: key {}: fov {} is out of range (expected 0 < fov < 180)",
                            i, *k.fovYDegrees));
        }
    }
    return {};
}

Camera cameraAt(const CameraPath& path, double time, const Camera& base) {
    Camera out = base;
    const auto& keys = path.keys;
    auto apply = [&](const CameraKey& k) {
        out.position = k.position;
        out.target = k.target;
        if (k.fovYDegrees) out.fovYDegrees = *k.fovYDegrees;
    };
    if (keys.empty()) return out;
    if (time <= keys.front().time) {
        apply(keys.front());
        return out;
    }
    if (time >= keys.back().time) {
        apply(keys.back());
        return out;
    }
    const auto next = std::upper_bound(keys.begin(), keys.end(), time,
                                       [](double t, const CameraKey& k) { return t < k.time; });
    const CameraKey& b = *next;
    const CameraKey& a = *(next - 1);
    const float s = float((time - a.time) / (b.time - a.time));
    out.position = glm::mix(a.position, b.position, s);
    out.target = glm::mix(a.target, b.target, s);
    const float fa = a.fovYDegrees.value_or(base.fovYDegrees);
    const float fb = b.fovYDegrees.value_or(base.fovYDegrees);
    out.fovYDegrees = fa + (fb - fa) * s;
    return out;
}

Result<Rig> rigAt(const Rig& rig, const Camera& camera, const ScreenEyes* eyes) {
    if (rig.screen) {
        // The screen moves with the camera: the framing camera moved as the centre eye was.
        const glm::mat4 move = glm::inverse(camera.viewFromWorld()) * rig.camera.viewFromWorld();
        Camera framing = rig.screenFraming;
        framing.position = glm::vec3(move * glm::vec4(framing.position, 1.0f));
        framing.target = glm::vec3(move * glm::vec4(framing.target, 1.0f));
        framing.up = glm::mat3(move) * framing.up;
        return makeScreenRig(framing, rig.screenConvergence, eyes ? *eyes : *rig.screen);
    }
    RigParams params;
    params.kind = rig.kind;
    params.columns = rig.columns;
    params.rows = rig.rows;
    params.interaxial = rig.interaxial;
    params.interaxialY = rig.interaxialY;
    params.convergence = rig.convergence;
    return makeRig(camera, params);
}

Status validateSampler(const Sampler& s) {
    if (s.input.empty()) return usageError("sampler: no keys");
    // 16 for transforms; morph target weights: one a target (face rigs have dozens).
    constexpr int kMaxComponents = 256;
    if (s.components < 1 || s.components > kMaxComponents) {
        return usageError(
            fmt::format("sampler: {} components (expected 1..{})", s.components, kMaxComponents));
    }
    if (s.rotation && s.components != 4) {
        return usageError(
            fmt::format("sampler: a rotation needs 4 components (got {})", s.components));
    }
    const std::size_t perKey = s.interpolation == Interpolation::CubicSpline ? 3 : 1;
    if (s.output.size() != s.input.size() * std::size_t(s.components) * perKey) {
        return usageError(fmt::format("sampler: {} output values for {} keys of {} components{}",
                                      s.output.size(), s.input.size(), s.components,
                                      perKey == 3 ? " (CUBICSPLINE: 3 per component)" : ""));
    }
    for (std::size_t i = 0; i < s.input.size(); ++i) {
        if (!std::isfinite(s.input[i]) || (i > 0 && s.input[i] <= s.input[i - 1])) {
            return usageError(fmt::format(
                "sampler: key {}: time {} is not finite or does not increase", i, s.input[i]));
        }
    }
    for (float v : s.output) {
        if (!std::isfinite(v)) return usageError("sampler: a non-finite output value");
    }
    return {};
}

namespace {
/// Where key `key`'s value starts in `output` (CUBICSPLINE: after its in-tangent).
std::size_t valueAt(const Sampler& s, std::size_t key) {
    const std::size_t c = std::size_t(s.components);
    return s.interpolation == Interpolation::CubicSpline ? (3 * key + 1) * c : key * c;
}
glm::quat quatAt(const Sampler& s, std::size_t key) {
    const float* q = &s.output[valueAt(s, key)];
    return glm::normalize(glm::quat(q[3], q[0], q[1], q[2]));  // glm: w first; glTF: x y z w
}
}  // namespace

std::vector<float> sample(const Sampler& s, double time) {
    const std::size_t n = s.input.size();
    const std::size_t c = std::size_t(s.components);
    auto keyValue = [&](std::size_t k) {
        if (s.rotation) {
            const glm::quat q = quatAt(s, k);
            return std::vector<float>{q.x, q.y, q.z, q.w};
        }
        return std::vector<float>(s.output.begin() + long(valueAt(s, k)),
                                  s.output.begin() + long(valueAt(s, k) + c));
    };
    if (n == 0) return std::vector<float>(c, 0.0f);
    if (time <= s.input.front()) return keyValue(0);
    if (time >= s.input.back()) return keyValue(n - 1);
    const std::size_t b = std::size_t(
        std::upper_bound(s.input.begin(), s.input.end(), float(time)) - s.input.begin());
    const std::size_t a = b - 1;
    if (s.interpolation == Interpolation::Step) return keyValue(a);
    const float t = float((time - s.input[a]) / (s.input[b] - s.input[a]));
    if (s.interpolation == Interpolation::CubicSpline) {
        // glTF 2.0 Appendix C: p(t) = (2t³-3t²+1)v_a + (t³-2t²+t)Δ·b_a + (-2t³+3t²)v_b +
        // (t³-t²)Δ·a_b, b_a the out-tangent of key a, a_b the in-tangent of key b.
        const float dt = s.input[b] - s.input[a], t2 = t * t, t3 = t2 * t;
        const float* va = &s.output[valueAt(s, a)];
        const float* vb = &s.output[valueAt(s, b)];
        const float* outA = va + c;  // key a's out-tangent
        const float* inB = vb - c;   // key b's in-tangent
        std::vector<float> out(c);
        for (std::size_t i = 0; i < c; ++i) {
            out[i] = (2 * t3 - 3 * t2 + 1) * va[i] + (t3 - 2 * t2 + t) * dt * outA[i] +
                     (-2 * t3 + 3 * t2) * vb[i] + (t3 - t2) * dt * inB[i];
        }
        if (s.rotation) {
            const glm::quat q = glm::normalize(glm::quat(out[3], out[0], out[1], out[2]));
            return {q.x, q.y, q.z, q.w};
        }
        return out;
    }
    if (s.rotation) {
        glm::quat qa = quatAt(s, a), qb = quatAt(s, b);
        if (glm::dot(qa, qb) < 0.0f) qb = -qb;  // the shorter arc
        const glm::quat q = glm::normalize(glm::slerp(qa, qb, t));
        return {q.x, q.y, q.z, q.w};
    }
    std::vector<float> out(c);
    for (std::size_t i = 0; i < c; ++i) {
        out[i] = s.output[a * c + i] + (s.output[b * c + i] - s.output[a * c + i]) * t;
    }
    return out;
}

glm::vec3 sampleVec3(const Sampler& s, double time) {
    const std::vector<float> v = sample(s, time);
    return {v.size() > 0 ? v[0] : 0.0f, v.size() > 1 ? v[1] : 0.0f, v.size() > 2 ? v[2] : 0.0f};
}

glm::quat sampleRotation(const Sampler& s, double time) {
    const std::vector<float> v = sample(s, time);
    if (v.size() < 4) return {1.0f, 0.0f, 0.0f, 0.0f};
    return glm::normalize(glm::quat(v[3], v[0], v[1], v[2]));
}

glm::mat4 nodeMatrixAt(const NodeAnimation& node, double time) {
    const glm::vec3 t =
        node.translation ? sampleVec3(*node.translation, time) : node.restTranslation;
    const glm::quat r = node.rotation ? sampleRotation(*node.rotation, time) : node.restRotation;
    const glm::vec3 sc = node.scale ? sampleVec3(*node.scale, time) : node.restScale;
    return glm::translate(glm::mat4(1.0f), t) * glm::mat4_cast(r) * glm::scale(glm::mat4(1.0f), sc);
}

Status validateSceneAnimation(const SceneAnimation& a) {
    for (std::size_t i = 0; i < a.nodes.size(); ++i) {
        const AnimatedNode& n = a.nodes[i];
        const std::string where = fmt::format("animation '{}': node {} ('{}')", a.name, i, n.name);
        if (n.parent < -1 || n.parent >= int(i)) {
            return inputError(fmt::format("{}: its parent {} is not before it", where, n.parent));
        }
        if (!n.animation) continue;
        for (const auto* s : {&n.animation->translation, &n.animation->rotation,
                              &n.animation->scale, &n.animation->weights}) {
            if (!*s) continue;
            if (Status st = validateSampler(**s); !st) {
                return inputError(fmt::format("{}: {}", where, st.message()));
            }
        }
    }
    for (const SceneAnimation::Target& t : a.instances) {
        if (t.node < 0 || t.node >= int(a.nodes.size()) || t.instance < 0) {
            return inputError(fmt::format("animation '{}': instance {} has no node {}", a.name,
                                          t.instance, t.node));
        }
    }
    for (const SceneAnimation::Skin& s : a.skins) {
        bool ok = s.instance >= 0 && s.meshNode >= -1 && s.meshNode < int(a.nodes.size());
        for (const int j : s.joints) ok = ok && j >= 0 && j < int(a.nodes.size());
        if (!ok) {
            return inputError(fmt::format("animation '{}': the skin of instance {} names a node "
                                          "it does not have",
                                          a.name, s.instance));
        }
    }
    if (a.cameraNode >= int(a.nodes.size())) {
        return inputError(fmt::format("animation '{}': no camera node {}", a.name, a.cameraNode));
    }
    return {};
}

std::vector<glm::mat4> nodeWorldsAt(const SceneAnimation& a, double time) {
    std::vector<glm::mat4> world(a.nodes.size());
    for (std::size_t i = 0; i < a.nodes.size(); ++i) {
        const AnimatedNode& n = a.nodes[i];
        const glm::mat4 local = n.animation ? nodeMatrixAt(*n.animation, time) : n.rest;
        world[i] = n.parent >= 0 ? world[std::size_t(n.parent)] * local : local;
    }
    return world;
}

std::vector<glm::mat4> skinMatrices(const SceneAnimation::Skin& skin,
                                    const std::vector<glm::mat4>& world) {
    std::vector<glm::mat4> m(skin.joints.size(), glm::mat4(1.0f));
    if (std::size_t(skin.meshNode) >= world.size() && skin.meshNode >= 0) return m;
    const glm::mat4 modelFromRoot =
        skin.meshNode >= 0 ? glm::inverse(world[std::size_t(skin.meshNode)]) : glm::mat4(1.0f);
    for (std::size_t j = 0; j < skin.joints.size(); ++j) {
        const int node = skin.joints[j];
        if (node < 0 || std::size_t(node) >= world.size()) continue;
        m[j] = modelFromRoot * world[std::size_t(node)] *
               (j < skin.inverseBind.size() ? skin.inverseBind[j] : glm::mat4(1.0f));
    }
    return m;
}

void animateScene(Scene& scene, const SceneAnimation& a, double time) {
    const std::vector<glm::mat4> world = nodeWorldsAt(a, time);
    for (const SceneAnimation::Target& t : a.instances) {
        if (t.instance < int(scene.instances.size())) {
            Instance& inst = scene.instances[std::size_t(t.instance)];
            inst.worldFromModel = t.worldFromRoot * world[std::size_t(t.node)];
            const std::optional<NodeAnimation>& na = a.nodes[std::size_t(t.node)].animation;
            if (na && na->weights && inst.mesh >= 0 && inst.mesh < int(scene.meshes.size()))
                applyMorphWeights(scene.meshes[std::size_t(inst.mesh)], sample(*na->weights, time));
        }
    }
    for (const SceneAnimation::Skin& skin : a.skins) {
        if (skin.instance < 0 || std::size_t(skin.instance) >= scene.instances.size()) continue;
        const int mesh = scene.instances[std::size_t(skin.instance)].mesh;
        if (mesh >= 0 && std::size_t(mesh) < scene.meshes.size())
            poseSkin(scene.meshes[std::size_t(mesh)], skinMatrices(skin, world));
    }
    if (a.cameraNode >= 0 && scene.camera) {
        scene.camera->worldFromCamera = a.cameraWorldFromRoot * world[std::size_t(a.cameraNode)];
    }
}

Camera cameraFromNode(const glm::mat4& worldFromCamera, const Camera& base) {
    Camera out = base;
    const glm::mat3 axes(worldFromCamera);
    glm::vec3 forward = axes * glm::vec3(0.0f, 0.0f, -1.0f);
    glm::vec3 up = axes * glm::vec3(0.0f, 1.0f, 0.0f);
    forward = glm::length(forward) > 0.0f ? glm::normalize(forward) : glm::vec3(0, 0, -1);
    up = glm::length(up) > 0.0f ? glm::normalize(up) : glm::vec3(0, 1, 0);
    out.position = glm::vec3(worldFromCamera[3]);
    out.up = up;
    out.target = out.position + forward * glm::length(base.target - base.position);
    return out;
}

void transformAnimation(SceneAnimation& a, const glm::mat4& worldFromScene) {
    for (SceneAnimation::Target& t : a.instances) t.worldFromRoot = worldFromScene * t.worldFromRoot;
    a.cameraWorldFromRoot = worldFromScene * a.cameraWorldFromRoot;
}

}  // namespace mvr

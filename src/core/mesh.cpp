#include "mvr/core/mesh.h"
#include "mvr/core/content_hash.h"

#include <cstring>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string_view>
#include <fstream>

#include <fmt/core.h>

namespace mvr {

Bounds Mesh::bounds() const {
    Bounds b;
    for (const glm::vec3& p : positions) b.extend(p);
    return b;
}

Status validateMesh(const Mesh& mesh, const std::string& what) {
    if (mesh.indices.empty()) return inputError(fmt::format("{}: has no triangles", what));
    if (mesh.indices.size() % 3 != 0) {
        return inputError(
            fmt::format("{}: index count {} is not a multiple of 3", what, mesh.indices.size()));
    }
    if (mesh.normals.size() != mesh.positions.size()) {
        return inputError(fmt::format("{}: {} normals for {} positions", what, mesh.normals.size(),
                                      mesh.positions.size()));
    }
    if (!mesh.texcoords.empty() && mesh.texcoords.size() != mesh.positions.size()) {
        return inputError(fmt::format("{}: {} texture coordinates for {} positions", what,
                                      mesh.texcoords.size(), mesh.positions.size()));
    }
    if ((!mesh.joints.empty() || !mesh.weights.empty()) &&
        (mesh.joints.size() != mesh.positions.size() ||
         mesh.weights.size() != mesh.positions.size() ||
         mesh.basePositions.size() != mesh.positions.size() ||
         mesh.baseNormals.size() != mesh.positions.size())) {
        return inputError(fmt::format("{}: {} joints and {} weights for {} positions", what,
                                      mesh.joints.size(), mesh.weights.size(),
                                      mesh.positions.size()));
    }
    if ((!mesh.joints1.empty() || !mesh.weights1.empty()) &&
        (mesh.joints.size() != mesh.positions.size() ||
         mesh.joints1.size() != mesh.positions.size() ||
         mesh.weights1.size() != mesh.positions.size())) {
        return inputError(fmt::format("{}: {} second joints and {} second weights for {} positions",
                                      what, mesh.joints1.size(), mesh.weights1.size(),
                                      mesh.positions.size()));
    }
    if (!mesh.tangents.empty() && mesh.tangents.size() != mesh.positions.size()) {
        return inputError(fmt::format("{}: {} tangents for {} positions", what,
                                      mesh.tangents.size(), mesh.positions.size()));
    }
    if (!mesh.colors.empty() && mesh.colors.size() != mesh.positions.size()) {
        return inputError(fmt::format("{}: {} vertex colours for {} positions", what,
                                      mesh.colors.size(), mesh.positions.size()));
    }
    for (std::size_t i = 0; i < mesh.colors.size(); ++i) {
        const glm::vec4& c = mesh.colors[i];
        for (int k = 0; k < 4; ++k) {
            if (!(c[k] >= 0.0f && c[k] <= 1.0f)) {
                return inputError(fmt::format(
                    "{}: vertex {} has the colour ({}, {}, {}, {}) (expected 0..1 each)", what, i,
                    c.x, c.y, c.z, c.w));
            }
        }
    }
    if (!mesh.morphTargets.empty()) {
        const std::size_t n = mesh.positions.size();
        if (mesh.basePositions.size() != n || mesh.baseNormals.size() != n)
            return inputError(fmt::format("{}: morph targets without the unmorphed mesh", what));
        for (std::size_t t = 0; t < mesh.morphTargets.size(); ++t) {
            const MorphTarget& m = mesh.morphTargets[t];
            if (m.positions.size() != n || (!m.normals.empty() && m.normals.size() != n))
                return inputError(fmt::format(
                    "{}: morph target {} has {} positions and {} normals for {} vertices", what,
                    t, m.positions.size(), m.normals.size(), n));
            for (std::size_t i = 0; i < n; ++i) {
                const glm::vec3 d = m.positions[i] + (m.normals.empty() ? glm::vec3(0.0f)
                                                                         : m.normals[i]);
                if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z))
                    return inputError(fmt::format(
                        "{}: morph target {} moves vertex {} by a non-finite amount", what, t, i));
            }
        }
    }
    for (std::size_t i = 0; i < mesh.indices.size(); ++i) {
        if (mesh.indices[i] >= mesh.positions.size()) {
            return inputError(fmt::format("{}: index {} out of range for {} vertices", what,
                                          mesh.indices[i], mesh.positions.size()));
        }
    }
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        const glm::vec3& p = mesh.positions[i];
        const glm::vec3& n = mesh.normals[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            return inputError(fmt::format("{}: vertex {} has a non-finite position", what, i));
        }
        if (std::abs(p.x) > kMaxCoordinate || std::abs(p.y) > kMaxCoordinate ||
            std::abs(p.z) > kMaxCoordinate) {
            return inputError(fmt::format(
                "{}: vertex {} at ({:g}, {:g}, {:g}) is out of range (coordinates at most {:g} "
                "in magnitude)",
                what, i, p.x, p.y, p.z, kMaxCoordinate));
        }
        if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z)) {
            return inputError(fmt::format("{}: vertex {} has a non-finite normal", what, i));
        }
    }
    // A mesh whose triangles all have zero area draws nothing: that is a degenerate mesh.
    bool anyArea = false;
    for (std::size_t t = 0; t + 2 < mesh.indices.size() && !anyArea; t += 3) {
        const glm::vec3 a = mesh.positions[mesh.indices[t]];
        const glm::vec3 e1 = mesh.positions[mesh.indices[t + 1]] - a;
        const glm::vec3 e2 = mesh.positions[mesh.indices[t + 2]] - a;
        anyArea = glm::length(glm::cross(e1, e2)) > 0.0f;
    }
    if (!anyArea)
        return inputError(fmt::format("{}: is degenerate (every triangle has zero area)", what));
    return {};
}

void computeSmoothNormals(Mesh& mesh) {
    mesh.normals.assign(mesh.positions.size(), glm::vec3(0.0f));
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const std::uint32_t i0 = mesh.indices[t], i1 = mesh.indices[t + 1],
                            i2 = mesh.indices[t + 2];
        // The cross product's length is twice the area: area weighting for free.
        const glm::vec3 n = glm::cross(mesh.positions[i1] - mesh.positions[i0],
                                       mesh.positions[i2] - mesh.positions[i0]);
        if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z)) continue;
        mesh.normals[i0] += n;
        mesh.normals[i1] += n;
        mesh.normals[i2] += n;
    }
    for (glm::vec3& n : mesh.normals) {
        const float len = glm::length(n);
        n = (len > 0.0f && std::isfinite(len)) ? n / len : glm::vec3(0.0f, 0.0f, 1.0f);
    }
}

namespace {
std::uint64_t hashBytes(std::uint64_t h, const void* data, std::size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    std::size_t i = 0;
    for (; i + 8 <= size; i += 8) {
        std::uint64_t w;
        std::memcpy(&w, p + i, 8);
        h = (h ^ w) * 0x100000001B3ull;
        h ^= h >> 29;
    }
    for (; i < size; ++i) h = (h ^ p[i]) * 0x100000001B3ull;
    return h ^ size;
}
}  // namespace

std::uint64_t contentHash(const Image& image) {
    std::uint64_t h = 0x84222325CBF29CE4ull ^ (std::uint64_t(image.width) << 32) ^
                      std::uint64_t(std::uint32_t(image.height));
    h = hashBytes(h, image.rgba.data(), image.rgba.size());
    return h == 0 ? 1 : h;
}

glm::vec4 decodeSrgbColor(glm::vec4 c) {
    for (int k = 0; k < 4; ++k) {
        float v = std::isnan(c[k]) ? 0.0f : std::clamp(c[k], 0.0f, 1.0f);
        if (k < 3) v = v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
        c[k] = v;
    }
    return c;
}

void applyMorphWeights(Mesh& mesh, const std::vector<float>& weights) {
    if (mesh.morphTargets.empty()) return;
    const std::size_t n = mesh.basePositions.size();
    mesh.positions = mesh.basePositions;
    mesh.normals = mesh.baseNormals;
    mesh.morphWeights.assign(mesh.morphTargets.size(), 0.0f);
    for (std::size_t t = 0; t < mesh.morphTargets.size() && t < weights.size(); ++t) {
        const float w = weights[t];
        mesh.morphWeights[t] = w;
        if (w == 0.0f) continue;
        const MorphTarget& m = mesh.morphTargets[t];
        for (std::size_t i = 0; i < n; ++i) mesh.positions[i] += w * m.positions[i];
        if (!mesh.computedNormals && !m.normals.empty())
            for (std::size_t i = 0; i < n; ++i) mesh.normals[i] += w * m.normals[i];
    }
    if (mesh.computedNormals) {
        computeSmoothNormals(mesh);
        return;
    }
    for (glm::vec3& v : mesh.normals) {
        const float len = glm::length(v);
        v = len > 0.0f && std::isfinite(len) ? v / len : glm::vec3(0.0f, 0.0f, 1.0f);
    }
}

void poseSkin(Mesh& mesh, const std::vector<glm::mat4>& jointMatrices) {
    const std::size_t n = mesh.basePositions.size();
    if (mesh.joints.size() != n || mesh.weights.size() != n || mesh.baseNormals.size() != n)
        return;
    const bool eight = mesh.joints1.size() == n && mesh.weights1.size() == n;
    // Influence k (0..7) of vertex i: JOINTS_0 / WEIGHTS_0, then JOINTS_1 / WEIGHTS_1.
    auto weightOf = [&](std::size_t i, int k) {
        return k < 4 ? mesh.weights[i][k] : mesh.weights1[i][k - 4];
    };
    auto jointOf = [&](std::size_t i, int k) -> std::size_t {
        return k < 4 ? mesh.joints[i][k] : mesh.joints1[i][k - 4];
    };
    const int influences = eight ? 8 : 4;
    auto unweighted = [&](std::size_t i) {
        const glm::vec4& a = mesh.weights[i];
        float sum = (a.x + a.y) + (a.z + a.w);
        if (eight) {
            const glm::vec4& b = mesh.weights1[i];
            sum += (b.x + b.y) + (b.z + b.w);
        }
        return sum == 0.0f;
    };
    if (mesh.morphTargets.empty()) {
        mesh.positions = mesh.basePositions;
        mesh.normals = mesh.baseNormals;
    } else {
        const std::vector<float> w = mesh.morphWeights;
        applyMorphWeights(mesh, w);  // the morphed pose, from the base again
    }
    // Normals through each joint's cofactor matrix (det · inverse transpose: defined for a
    // joint scaled to nothing, as files do to hide a part; the normalisation below removes det).
    std::vector<glm::mat3> normalMatrices(jointMatrices.size());
    for (std::size_t j = 0; j < jointMatrices.size(); ++j) {
        const glm::mat3 a(jointMatrices[j]);
        normalMatrices[j] = glm::mat3(glm::cross(a[1], a[2]), glm::cross(a[2], a[0]),
                                      glm::cross(a[0], a[1]));
    }
    for (std::size_t i = 0; i < n; ++i) {
        if (unweighted(i)) continue;  // left as it is
        const glm::vec4 p(mesh.positions[i], 1.0f);
        glm::vec4 sp(0.0f);
        glm::vec3 sn(0.0f);
        for (int k = 0; k < influences; ++k) {
            const float w = weightOf(i, k);
            if (w == 0.0f) continue;
            const std::size_t j = jointOf(i, k);
            if (j < jointMatrices.size()) {
                sp += w * (jointMatrices[j] * p);
                sn += w * (normalMatrices[j] * mesh.normals[i]);
            } else {
                sp += w * p;
                sn += w * mesh.normals[i];
            }
        }
        mesh.positions[i] = glm::vec3(sp);
        const float len = glm::length(sn);
        mesh.normals[i] = len > 0.0f && std::isfinite(len) ? sn / len : mesh.normals[i];
    }
    if (mesh.baseTangents.size() == n && mesh.tangents.size() == n) {
        for (std::size_t i = 0; i < n; ++i) {
            if (unweighted(i)) {
                mesh.tangents[i] = mesh.baseTangents[i];
                continue;
            }
            const glm::vec3 t(mesh.baseTangents[i]);
            glm::vec3 st(0.0f);
            for (int k = 0; k < influences; ++k) {
                const float w = weightOf(i, k);
                const std::size_t j = jointOf(i, k);
                if (w != 0.0f) st += w * (j < jointMatrices.size() ? glm::mat3(jointMatrices[j]) * t : t);
            }
            const float len = glm::length(st);
            mesh.tangents[i] = glm::vec4(len > 0.0f && std::isfinite(len) ? st / len : t,
                                         mesh.baseTangents[i].w);
        }
    }
}

std::uint64_t contentHash(const Mesh& m) {
    std::uint64_t h = 0xCBF29CE484222325ull;
    h = hashBytes(h, m.positions.data(), m.positions.size() * sizeof(glm::vec3));
    h = hashBytes(h, m.normals.data(), m.normals.size() * sizeof(glm::vec3));
    h = hashBytes(h, m.indices.data(), m.indices.size() * sizeof(std::uint32_t));
    h = hashBytes(h, m.texcoords.data(), m.texcoords.size() * sizeof(glm::vec2));
    h = hashBytes(h, m.colors.data(), m.colors.size() * sizeof(glm::vec4));
    h = hashBytes(h, m.tangents.data(), m.tangents.size() * sizeof(glm::vec4));
    return h;
}

}  // namespace mvr

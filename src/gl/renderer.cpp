#include "renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string_view>

#include <fmt/format.h>

namespace mvr::gl::detail {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// MVR_GL_GS_EMIT_LIMIT=N: programs whose geometry shader emits more than N vertices are
// treated as refused by the driver (0 or unset: none are).
int viewsPerTarget(TargetKind target) {
    // MVR_GL_VIEWS_PER_TARGET=N measures other bounds (bench the read-back) without a build.
    const char* v = std::getenv("MVR_GL_VIEWS_PER_TARGET");
    if (const int n = v ? std::atoi(v) : 0; n > 0) return std::min(n, kMaxViews);
    return target == TargetKind::Tiled ? kTilesPerTarget : kLayersPerTarget;
}

// Read when a program is built (a test sets it before making a backend).
int gsEmitLimit() {
    const char* v = std::getenv("MVR_GL_GS_EMIT_LIMIT");
    return v ? std::max(0, std::atoi(v)) : 0;
}

// Attributes 0 position, 1 normal, 2 texture coordinate, 3 (flat arrays) the face's centroid,
// 4 the vertex colour (read only by VERTEX_COLORS programs), 5 the tangent (NORMAL_MAPS
// programs; none: left disabled, the constant (0, 0, 0, 1) that setCommonState sets).
void bindVertexArray(GLuint vao, GLuint positions, GLuint normals, GLuint texcoords, GLuint indices,
                     GLuint colors, GLuint centers = 0, GLuint tangents = 0) {
    glVertexArrayVertexBuffer(vao, 0, positions, 0, sizeof(glm::vec3));
    glVertexArrayVertexBuffer(vao, 1, normals, 0, sizeof(glm::vec3));
    glVertexArrayVertexBuffer(vao, 2, texcoords, 0, sizeof(glm::vec2));
    glVertexArrayElementBuffer(vao, indices);
    for (GLuint a = 0; a < 3; ++a) {
        glEnableVertexArrayAttrib(vao, a);
        glVertexArrayAttribFormat(vao, a, a == 2 ? 2 : 3, GL_FLOAT, GL_FALSE, 0);
        glVertexArrayAttribBinding(vao, a, a);
    }
    glVertexArrayVertexBuffer(vao, 4, colors, 0, sizeof(glm::vec4));
    glEnableVertexArrayAttrib(vao, 4);
    glVertexArrayAttribFormat(vao, 4, 4, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao, 4, 4);
    if (centers) {
        glVertexArrayVertexBuffer(vao, 3, centers, 0, sizeof(glm::vec3));
        glEnableVertexArrayAttrib(vao, 3);
        glVertexArrayAttribFormat(vao, 3, 3, GL_FLOAT, GL_FALSE, 0);
        glVertexArrayAttribBinding(vao, 3, 3);
    }
    if (tangents) {
        glVertexArrayVertexBuffer(vao, 5, tangents, 0, sizeof(glm::vec4));
        glEnableVertexArrayAttrib(vao, 5);
        glVertexArrayAttribFormat(vao, 5, 4, GL_FLOAT, GL_FALSE, 0);
        glVertexArrayAttribBinding(vao, 5, 5);
    }
}

template <class T>
Buffer makeBuffer(const std::vector<T>& data) {
    Buffer b = createBuffer();
    // Zero-sized storage is an error; an empty array gets one element's worth.
    glNamedBufferStorage(b.get(), std::max<std::size_t>(data.size(), 1) * sizeof(T),
                         data.empty() ? nullptr : data.data(), 0);
    return b;
}

}  // namespace

Renderer::~Renderer() {
    if (mGpu && !(mContext && mContext->makeCurrent())) {
        // Without its context current no GL object may be deleted through GL calls (on
        // NVIDIA's driver that crashes): the names go with the context, the owners are left.
        static_cast<void>(mGpu.release());
        return;
    }
    mGpu.reset();  // while the context is current; mContext goes after it
}

Status Renderer::ensureContext() {
    if (mContextStatus) {
        if (!*mContextStatus) return *mContextStatus;
        return mContext->makeCurrent();
    }
    auto ctx = EglContext::create();
    if (!ctx) {
        mContextStatus = ctx.status();
        return *mContextStatus;
    }
    mContext = std::move(ctx).value();
    mCaps = GlCaps::query();
    mGpu = std::make_unique<GpuObjects>();
    mGpu->frameUbo = createBuffer();
    glNamedBufferStorage(mGpu->frameUbo.get(), sizeof(FrameBlock), nullptr, GL_DYNAMIC_STORAGE_BIT);
    mGpu->emptyVao = createVertexArray();
    mContextStatus = checkGlError("creating the backend's objects");
    if (!*mContextStatus) return *mContextStatus;
    if (mCaps.maxUniformBlockSize < static_cast<int>(sizeof(FrameBlock))) {
        mContextStatus = unsupportedError(
            fmt::format("mvr::gl: GL_MAX_UNIFORM_BLOCK_SIZE = {} is below the {} bytes mvr needs",
                        mCaps.maxUniformBlockSize, sizeof(FrameBlock)));
    }
    return *mContextStatus;
}

std::vector<std::string> Renderer::info() {
    std::vector<std::string> lines;
    if (Status s = ensureContext(); !s) {
        lines.push_back("gl: unavailable: " + s.message());
        return lines;
    }
    lines.push_back(fmt::format("EGL platform: {} (EGL {} {})", mContext->platform(),
                                mContext->eglVersion(), mContext->eglVendor()));
    for (std::string& l : mCaps.describe()) lines.push_back(std::move(l));
    mVertexColors = false;  // the limits of a scene without vertex colours
    mNormalMaps = false;    // nor normal maps
    mEnvironment = false;   // nor an environment
    for (const GlMethod& m : glMethods()) {
        if (m.measuresExact) continue;
        if (const std::string why = m.missing ? m.missing(mCaps) : ""; !why.empty()) {
            lines.push_back(fmt::format("method {}: unsupported: {}", m.name, why));
            continue;
        }
        if (m.fixedViews > 0) {
            lines.push_back(
                fmt::format("method {}: supported, up to {} views", m.name, m.fixedViews));
            continue;
        }
        // What a pass takes: the driver's declared limits, what it links (a geometry-shader
        // loop's program is built at the declared count, and at smaller ones when that is
        // refused) and the bounded target.
        const int bound = viewsPerTarget(m.target);
        auto describe = [&](Shading sh) {
            const int declared = viewLimit(m, sh, 1024, 768);
            const bool loop = methodProgram(m, mCaps, sh, 1).gsMaxVertices > 0;
            const int linked = loop ? linkedViewLimit(m, sh, false, declared) : declared;
            std::string why = fmt::format("declared {}", declared);
            if (linked < declared) why += fmt::format(", the driver links {}", linked);
            return std::pair{std::min(linked, bound), why};
        };
        const auto [pf, wf] = describe(Shading::Flat);
        const auto [pp, wp] = describe(Shading::Pixel);
        const std::string target = fmt::format("targets of at most {} views", bound);
        if (pf == pp && wf == wp) {
            lines.push_back(
                fmt::format("method {}: supported, {} views per pass ({}; {}), "
                            "batches beyond",
                            m.name, pf, wf, target));
        } else {
            lines.push_back(
                fmt::format("method {}: supported, {} views per pass (flat/vertex: {}), "
                            "{} (pixel: {}) at 1024x768 ({}), batches beyond",
                            m.name, pf, wf, pp, wp, target));
        }
    }
    return lines;
}

Status Renderer::supports(const std::string& method) {
    const GlMethod* m = findMethod(method);
    if (!m) {
        return usageError(fmt::format("gl: unknown method '{}' (expected one of: {})", method,
                                      fmt::join(methodNames(), ", ")));
    }
    return supportsMethod(*m);
}

Status Renderer::supportsMethod(const GlMethod& method) {
    if (Status s = ensureContext(); !s) return s;
    return driverSupport(method, mCaps);
}

Result<TileLayout> Renderer::tileLayout(const Rig& rig, int width, int height) const {
    const int n = rig.viewCount();
    const int maxW = std::min(mCaps.maxTextureSize, mCaps.maxViewportDims[0]);
    const int maxH = std::min(mCaps.maxTextureSize, mCaps.maxViewportDims[1]);
    TileLayout t;
    t.width = width;
    t.height = height;
    // The rig's own arrangement (a row: side by side; kalaiah2007's C×R grids) when it fits,
    // else as many columns as fit.
    if (rig.columns * rig.rows == n && rig.columns * width <= maxW && rig.rows * height <= maxH) {
        t.columns = rig.columns;
        t.rows = rig.rows;
    } else {
        t.columns = std::max(1, std::min(n, maxW / std::max(width, 1)));
        t.rows = (n + t.columns - 1) / t.columns;
    }
    if (t.columns * width > maxW || t.rows * height > maxH) {
        return unsupportedError(
            fmt::format("{} views of {}x{} do not fit in one target of at most {}x{} "
                        "(GL_MAX_TEXTURE_SIZE / GL_MAX_VIEWPORT_DIMS)",
                        n, width, height, maxW, maxH));
    }
    return t;
}

int Renderer::viewLimit(const GlMethod& m, Shading shading, int width, int height) const {
    return detail::viewLimit(m, mCaps, shading, width, height,
                             mNormalMaps && shading == Shading::Pixel);
}

bool Renderer::drawsNormalMaps(const Scene& scene, const RenderSettings& s) {
    if (s.shading != Shading::Pixel) return false;  // flat and vertex shading ignore them
    for (const Instance& inst : scene.instances) {
        if (inst.material.normalTexture >= 0 && inst.mesh >= 0 &&
            std::size_t(inst.mesh) < scene.meshes.size() &&
            !scene.meshes[std::size_t(inst.mesh)].tangents.empty())
            return true;
    }
    return false;
}

ProgramDesc Renderer::passProgram(const GlMethod& method, Shading shading, int views,
                                  bool shadows, bool perViewEye) const {
    ProgramDesc desc = methodProgram(method, mCaps, shading, views);
    if (shadows) addDefine(desc, "SHADOWS");  // shadow_maps.cpp
    if (mVertexColors) addDefine(desc, "VERTEX_COLORS");
    // The world tangent as one more varying (4 components: viewLimit counts them).
    if (mNormalMaps && shading == Shading::Pixel) addDefine(desc, "NORMAL_MAPS");
    // Image lighting: uniforms and textures only (the SH in the Frame block, units 8 and 9),
    // no varying, so the view limits stay as they are.
    if (mEnvironment) addDefine(desc, "ENVIRONMENT");
    if (perViewEye) {
        // The fragment's view from gl_Layer / gl_ViewportIndex / the MRT flag / uView, or
        // (kalaiah, multiview) a flat output of the vertex shader: no geometry shader output
        // grows, so the views a pass takes stay as they are.
        addDefine(desc, "PER_VIEW_EYE");
    }
    return desc;
}

int Renderer::passLimit(const GlMethod& method, Shading shading, int width, int height,
                        bool shadows, Status* why) {
    const int limit = viewLimit(method, shading, width, height);
    if (method.fixedViews > 0 || limit < 1) return limit;
    return linkedViewLimit(method, shading, shadows, std::min(limit, viewsPerTarget(method.target)),
                           why);
}

int Renderer::linkedViewLimit(const GlMethod& method, Shading shading, bool shadows, int limit,
                              Status* why) {
    if (method.fixedViews > 0 || limit < 1) return limit;
    const std::string key =
        fmt::format("{}/{}/{}/{}/{}/{}", method.name, shadingName(shading), shadows,
                    mVertexColors, mNormalMaps && shading == Shading::Pixel, mEnvironment);
    const auto known = mLinkedViewLimit.find(key);  // a count the driver refused above
    // The count asked first; when the driver refuses that program, the largest count it links
    // (a smaller loop emits less, so the counts that link are 1..k).
    auto links = [&](int n) {
        return program(method.name, passProgram(method, shading, n, shadows)).status();
    };
    if (known != mLinkedViewLimit.end() && known->second < limit) {
        if (known->second < 1 && why) *why = links(1);
        return known->second;
    }
    if (links(limit)) return limit;  // cached after the first build: no cost next time
    int lo = 0, hi = limit;          // hi is refused; lo links (0: none known to)
    while (hi - lo > 1) {
        const int mid = lo + (hi - lo) / 2;
        (links(mid) ? lo : hi) = mid;
    }
    if (lo < 1 && why) *why = links(1);
    mLinkedViewLimit[key] = lo;
    return lo;
}

Status Renderer::checkViews(const GlMethod& m, int views, const RenderSettings& s) const {
    if (shadesFromEachEye(s) && m.perViewEyeMissing) {
        if (const std::string why = m.perViewEyeMissing(mCaps); !why.empty())
            return unsupportedError(fmt::format("gl: {}: --specular per-view {}", m.name, why));
    }
    // Colour (4 bytes) + depth (4 bytes) per pixel per view on the GPU side, the same again
    // for the images handed back, and multisampled (samples > 1 reaches here only then) the
    // targets' twins, N times that a view of a pass (at most a target's views): refuse what
    // would not fit in memory instead of failing (or being killed) halfway.
    constexpr double kBudgetBytes = 4.0 * 1024 * 1024 * 1024;
    const double pixels = double(s.width) * s.height;
    const int passViews = std::min(views, viewsPerTarget(m.target));
    const double bytes = 8.0 * pixels * views +
                         (s.samples > 1 ? 8.0 * s.samples * pixels * passViews : 0.0);
    if (bytes > kBudgetBytes) {
        return unsupportedError(fmt::format(
            "gl: {} views of {}x{}{} need {:.1f} GiB of colour + depth targets (limit {:.0f} "
            "GiB)",
            views, s.width, s.height,
            s.samples > 1 ? fmt::format(" at {} samples a pixel", s.samples) : "",
            bytes / (1024.0 * 1024 * 1024), kBudgetBytes / (1024.0 * 1024 * 1024)));
    }
    return checkMethodViews(m, mCaps, views, s, mNormalMaps && s.shading == Shading::Pixel);
}

Status Renderer::prepareScene(const Scene& scene, Frame& frame, std::uint64_t& sceneKey) {
    ++mUseCounter;
    sceneKey = 0x9E3779B97F4A7C15ull;
    frame.meshes.assign(scene.meshes.size(), nullptr);
    for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
        const Mesh& src = scene.meshes[i];
        const std::uint64_t key = contentHash(src);
        sceneKey = (sceneKey ^ key) * 0x100000001B3ull;
        auto it = mGpu->meshes.find(key);
        if (it == mGpu->meshes.end()) {
            // Keep a few meshes beyond this scene's; drop the least recently used of the
            // others. Never one this frame uses already (frame.meshes points at it): a scene
            // of more meshes than the cache keeps (a glTF file of dozens of primitives) would
            // otherwise draw a deleted vertex array (GL_INVALID_OPERATION).
            evictLeastRecentlyUsed(mGpu->meshes, kMeshesKept, mUseCounter);
            GpuMesh g;
            g.indexCount = static_cast<GLsizei>(src.indices.size());
            g.triangleCount = static_cast<GLsizei>(src.triangleCount());
            g.bounds = src.bounds();
            g.positions = createBuffer();
            g.normals = createBuffer();
            g.indices = createBuffer();
            glNamedBufferStorage(g.positions.get(), src.positions.size() * sizeof(glm::vec3),
                                 src.positions.data(), 0);
            glNamedBufferStorage(g.normals.get(), src.normals.size() * sizeof(glm::vec3),
                                 src.normals.data(), 0);
            glNamedBufferStorage(g.indices.get(), src.indices.size() * sizeof(std::uint32_t),
                                 src.indices.data(), 0);
            std::vector<glm::vec2> uv = src.texcoords;
            uv.resize(src.positions.size(), glm::vec2(0.0f));
            g.texcoords = makeBuffer(uv);
            std::vector<glm::vec4> colors = src.colors;
            colors.resize(src.positions.size(), glm::vec4(1.0f));
            g.colors = makeBuffer(colors);
            if (!src.tangents.empty()) g.tangents = makeBuffer(src.tangents);
            g.vao = createVertexArray();
            bindVertexArray(g.vao.get(), g.positions.get(), g.normals.get(), g.texcoords.get(),
                            g.indices.get(), g.colors.get(), 0, g.tangents.get());

            // Provoking-vertex arrays for flat shading: rotate each triangle (keeping its
            // winding) so that its last vertex is one no earlier triangle used as provoking
            // vertex; duplicate a vertex when all three are taken.
            std::vector<glm::vec3> pos = src.positions;
            std::vector<glm::vec3> face(pos.size(), glm::vec3(0.0f));
            std::vector<glm::vec2> flatUv = uv;
            std::vector<glm::vec4> flatColors = colors;
            std::vector<glm::vec3> centers(pos.size(), glm::vec3(0.0f));
            std::vector<char> used(pos.size(), 0);
            std::vector<std::uint32_t> idx(src.indices.size());
            for (std::size_t t = 0; t < src.triangleCount(); ++t) {
                std::uint32_t v[3] = {src.indices[3 * t], src.indices[3 * t + 1],
                                      src.indices[3 * t + 2]};
                const glm::vec3 n = glm::cross(src.positions[v[1]] - src.positions[v[0]],
                                               src.positions[v[2]] - src.positions[v[0]]);
                // Before v[2] may be replaced by a duplicate's index (past src.positions).
                const glm::vec3 center =
                    (src.positions[v[0]] + src.positions[v[1]] + src.positions[v[2]]) / 3.0f;
                int pick = !used[v[2]] ? 2 : !used[v[0]] ? 0 : !used[v[1]] ? 1 : -1;
                if (pick < 0) {
                    v[2] = static_cast<std::uint32_t>(pos.size());
                    pos.push_back(src.positions[src.indices[3 * t + 2]]);
                    flatUv.push_back(uv[src.indices[3 * t + 2]]);
                    flatColors.push_back(colors[src.indices[3 * t + 2]]);
                    centers.emplace_back(0.0f);
                    face.emplace_back(0.0f);
                    used.push_back(0);
                    pick = 2;
                }
                const std::uint32_t r[3] = {v[(pick + 1) % 3], v[(pick + 2) % 3], v[pick]};
                used[r[2]] = 1;
                face[r[2]] = n;
                centers[r[2]] = center;
                std::copy(r, r + 3, idx.begin() + static_cast<std::ptrdiff_t>(3 * t));
            }
            g.flatPositions = createBuffer();
            g.flatNormals = createBuffer();
            g.flatIndices = createBuffer();
            glNamedBufferStorage(g.flatPositions.get(), pos.size() * sizeof(glm::vec3), pos.data(),
                                 0);
            glNamedBufferStorage(g.flatNormals.get(), face.size() * sizeof(glm::vec3), face.data(),
                                 0);
            glNamedBufferStorage(g.flatIndices.get(), idx.size() * sizeof(std::uint32_t),
                                 idx.data(), 0);
            g.flatTexcoords = makeBuffer(flatUv);
            g.flatCenters = makeBuffer(centers);
            g.flatColors = makeBuffer(flatColors);
            g.flatVao = createVertexArray();
            bindVertexArray(g.flatVao.get(), g.flatPositions.get(), g.flatNormals.get(),
                            g.flatTexcoords.get(), g.flatIndices.get(), g.flatColors.get(),
                            g.flatCenters.get());
            if (Status s = checkGlError("uploading a mesh"); !s) return s;
            it = mGpu->meshes.emplace(key, std::move(g)).first;
        }
        it->second.lastUse = mUseCounter;
        frame.meshes[i] = &it->second;
    }
    sceneKey ^= scene.instances.size() * 0x9E3779B1ull;
    return prepareTextures(scene, frame, sceneKey);
}

Status Renderer::ensureKalaiahBuffers(GpuMesh& g, const Mesh& src, int views) {
    if (!g.kalaiahTriangles) {
        // Per triangle: p0 p1 p2 n0 n1 n2 (model space), the attributes kalaiah2007 packs
        // into unused slots; one instance of the dummy array per triangle.
        std::vector<glm::vec3> data(src.triangleCount() * 6);
        for (std::size_t t = 0; t < src.triangleCount(); ++t) {
            for (int c = 0; c < 3; ++c) {
                const std::uint32_t v = src.indices[3 * t + c];
                data[6 * t + c] = src.positions[v];
                data[6 * t + 3 + c] = src.normals[v];
            }
        }
        g.kalaiahTriangles = createBuffer();
        glNamedBufferStorage(g.kalaiahTriangles.get(), data.size() * sizeof(glm::vec3), data.data(),
                             0);
        g.kalaiahVao = createVertexArray();
        const GLuint vao = g.kalaiahVao.get();
        glVertexArrayVertexBuffer(vao, 1, g.kalaiahTriangles.get(), 0, 6 * sizeof(glm::vec3));
        glVertexArrayBindingDivisor(vao, 1, 1);
        for (GLuint a = 1; a <= 6; ++a) {
            glEnableVertexArrayAttrib(vao, a);
            glVertexArrayAttribFormat(vao, a, 3, GL_FLOAT, GL_FALSE,
                                      (a - 1) * static_cast<GLuint>(sizeof(glm::vec3)));
            glVertexArrayAttribBinding(vao, a, 1);
        }
        // Per triangle: t0 t1 t2 (attributes 7–9).
        std::vector<glm::vec2> uv(src.triangleCount() * 3, glm::vec2(0.0f));
        if (!src.texcoords.empty()) {
            for (std::size_t k = 0; k < uv.size(); ++k) uv[k] = src.texcoords[src.indices[k]];
        }
        g.kalaiahTexcoords = makeBuffer(uv);
        glVertexArrayVertexBuffer(vao, 2, g.kalaiahTexcoords.get(), 0, 3 * sizeof(glm::vec2));
        glVertexArrayBindingDivisor(vao, 2, 1);
        for (GLuint a = 7; a <= 9; ++a) {
            glEnableVertexArrayAttrib(vao, a);
            glVertexArrayAttribFormat(vao, a, 2, GL_FLOAT, GL_FALSE,
                                      (a - 7) * static_cast<GLuint>(sizeof(glm::vec2)));
            glVertexArrayAttribBinding(vao, a, 2);
        }
        // Per triangle: c0 c1 c2 (attributes 10–12; white when the mesh has none).
        std::vector<glm::vec4> rgba(src.triangleCount() * 3, glm::vec4(1.0f));
        if (!src.colors.empty()) {
            for (std::size_t k = 0; k < rgba.size(); ++k) rgba[k] = src.colors[src.indices[k]];
        }
        g.kalaiahColors = makeBuffer(rgba);
        glVertexArrayVertexBuffer(vao, 3, g.kalaiahColors.get(), 0, 3 * sizeof(glm::vec4));
        glVertexArrayBindingDivisor(vao, 3, 1);
        for (GLuint a = 10; a <= 12; ++a) {
            glEnableVertexArrayAttrib(vao, a);
            glVertexArrayAttribFormat(vao, a, 4, GL_FLOAT, GL_FALSE,
                                      (a - 10) * static_cast<GLuint>(sizeof(glm::vec4)));
            glVertexArrayAttribBinding(vao, a, 3);
        }
        // Per triangle: the corners' tangents (attributes 13–15), when the mesh has them; else
        // disabled, the constant (0, 0, 0, 1) (setCommonState).
        if (!src.tangents.empty()) {
            std::vector<glm::vec4> tangents(src.triangleCount() * 3);
            for (std::size_t k = 0; k < tangents.size(); ++k)
                tangents[k] = src.tangents[src.indices[k]];
            g.kalaiahTangents = makeBuffer(tangents);
            glVertexArrayVertexBuffer(vao, 4, g.kalaiahTangents.get(), 0, 3 * sizeof(glm::vec4));
            glVertexArrayBindingDivisor(vao, 4, 1);
            for (GLuint a = 13; a <= 15; ++a) {
                glEnableVertexArrayAttrib(vao, a);
                glVertexArrayAttribFormat(vao, a, 4, GL_FLOAT, GL_FALSE,
                                          (a - 13) * static_cast<GLuint>(sizeof(glm::vec4)));
                glVertexArrayAttribBinding(vao, a, 4);
            }
        }
        glEnableVertexArrayAttrib(vao, 0);
        glVertexArrayAttribIFormat(vao, 0, 2, GL_INT, 0);
        glVertexArrayAttribBinding(vao, 0, 0);
    }
    if (g.kalaiahViews < views) {
        // V dummy triangles: vertex i of triangle j is (i, j); a pass of fewer views draws the
        // first ones.
        std::vector<glm::ivec2> dummy;
        for (int j = 0; j < views; ++j)
            for (int i = 0; i < 3; ++i) dummy.emplace_back(i, j);
        g.kalaiahDummy = createBuffer();
        glNamedBufferStorage(g.kalaiahDummy.get(), dummy.size() * sizeof(glm::ivec2), dummy.data(),
                             0);
        glVertexArrayVertexBuffer(g.kalaiahVao.get(), 0, g.kalaiahDummy.get(), 0,
                                  sizeof(glm::ivec2));
        g.kalaiahViews = views;
    }
    return checkGlError("uploading the kalaiah2007 arrays");
}

void Renderer::uploadFrameBlock(const Frame& f) {
    const TileLayout* tiles = f.tiles ? &*f.tiles : nullptr;
    FrameBlock b{};
    for (int v = 0; v < f.views; ++v) {
        b.clipFromWorld[v] = f.rig->views[static_cast<std::size_t>(v)].clipFromWorld();
        b.viewEye[v] = glm::vec4(f.rig->views[static_cast<std::size_t>(v)].eyeWorld, 1.0f);
        if (tiles) {
            // ndc' = (ndc + 1) / C + 2c / C − 1, i.e. clip.x' = clip.x / C + clip.w ((1 + 2c) / C − 1).
            // In NDC, whose y points up whatever the clip origin: column c, row R − 1 − r.
            const float cx = static_cast<float>(v % tiles->columns);
            const float cy = static_cast<float>(tiles->rows - 1 - v / tiles->columns);
            const float nc = static_cast<float>(tiles->columns);
            const float nr = static_cast<float>(tiles->rows);
            b.tile[v] = {1.0f / nc, 1.0f / nr, (1.0f + 2.0f * cx) / nc - 1.0f,
                         (1.0f + 2.0f * cy) / nr - 1.0f};
        }
    }
    const auto& lights = f.scene->lights;
    for (std::size_t i = 0; i < lights.size() && i < kMaxLights; ++i) {
        b.lightDir[i] = glm::vec4(lights[i].towardLight, 0.0f);
        b.lightColor[i] = glm::vec4(lights[i].color, 0.0f);
        const float type = lights[i].type == LightType::Point  ? 1.0f
                           : lights[i].type == LightType::Spot ? 2.0f
                                                               : 0.0f;
        b.lightPos[i] = glm::vec4(lights[i].position, type);
        b.lightCone[i] =
            glm::vec4(lights[i].range, lights[i].innerConeCos, lights[i].outerConeCos, 0.0f);
    }
    b.ambient = glm::vec4(f.scene->ambient, float(int(f.scene->tonemap)));  // w: finishColor
    b.centerEye = glm::vec4(f.rig->centerEye(), 1.0f);
    b.counts = {static_cast<int>(std::min<std::size_t>(lights.size(), kMaxLights)), f.views,
                f.settings->width, f.settings->height};
    if (f.scene->environment) {
        for (std::size_t k = 0; k < 9; ++k)
            b.envSh[k] = glm::vec4(f.scene->environment->sh[k], 0.0f);
    }
    glNamedBufferSubData(mGpu->frameUbo.get(), 0, sizeof(FrameBlock), &b);
    glBindBufferBase(GL_UNIFORM_BUFFER, 0, mGpu->frameUbo.get());
}

Result<GLuint> Renderer::program(const std::string& label, const ProgramDesc& d) {
    const std::string key = d.vsExtensions + d.defines + (d.geometry ? "GS" : "");
    if (auto it = mGpu->programs.find(key); it != mGpu->programs.end()) return it->second.get();
    if (auto it = mProgramErrors.find(key); it != mProgramErrors.end()) return it->second;
    if (const int emit = gsEmitLimit(); emit > 0 && d.gsMaxVertices > emit) {
        // A driver that declares more than it links (NVIDIA: "error C6033: Hardware
        // limitation reached, can only emit 78 vertices of this size"), reproduced anywhere.
        Status s = internalError(fmt::format(
            "gl: {}: the geometry shader emits {} vertices and the driver refuses more than "
            "{} (MVR_GL_GS_EMIT_LIMIT)",
            label, d.gsMaxVertices, emit));
        mProgramErrors.emplace(key, s);
        return s;
    }
    auto p = buildProgram(d);
    if (!p) {
        Status s(p.status().code(), fmt::format("gl: {}: {}", label, p.status().message()));
        mProgramErrors.emplace(key, s);
        return s;
    }
    const GLuint name = p->get();
    mGpu->programs.emplace(key, std::move(p).value());
    return name;
}

void Renderer::setInstanceUniforms(GLuint prog, const Instance& inst) {
    const glm::mat4& m = inst.worldFromModel;
    const glm::mat3 m3(m);
    const glm::mat3 invT = glm::transpose(glm::inverse(m3));
    const glm::mat4 normalFromModel(invT);
    const glm::mat4 cofactor(invT * glm::determinant(m3));
    glProgramUniformMatrix4fv(prog, 1, 1, GL_FALSE, &m[0][0]);
    glProgramUniformMatrix4fv(prog, 2, 1, GL_FALSE, &normalFromModel[0][0]);
    glProgramUniformMatrix4fv(prog, 3, 1, GL_FALSE, &cofactor[0][0]);
    glProgramUniform4f(prog, 4, inst.material.albedo.x, inst.material.albedo.y,
                       inst.material.albedo.z, inst.material.specular);
    glProgramUniform1f(prog, 5, inst.material.shininess);
    const Material& mat = inst.material;
    const int mode = mat.alphaMode == AlphaMode::Mask    ? 1
                     : mat.alphaMode == AlphaMode::Blend ? 2
                                                         : 0;
    // uMatFlags.x: the texture slots present, one bit each (shaders.cpp); any of them makes the
    // instance textured (hasTexture: split lighting, the uv path), the base colour's bit alone
    // picks its texel. The normal map's (16) is sampled by NORMAL_MAPS programs only.
    const int slots = (mat.baseColorTexture >= 0 ? 1 : 0) |
                      (mat.metallicRoughnessTexture >= 0 ? 2 : 0) |
                      (mat.occlusionTexture >= 0 ? 4 : 0) | (mat.emissiveTexture >= 0 ? 8 : 0) |
                      (mat.normalTexture >= 0 ? 16 : 0);
    glProgramUniform4i(prog, 6, slots, mode, mat.doubleSided ? 1 : 0, int(mat.model));
    glProgramUniform3f(prog, 7, mat.alpha, mat.alphaCutoff, mat.occlusionStrength);
    glProgramUniform2f(prog, 20, mat.metallic, mat.roughness);
    glProgramUniform3f(prog, 21, mat.emissive.x, mat.emissive.y, mat.emissive.z);
    if (mNormalMaps) glProgramUniform1f(prog, 22, mat.normalScale);  // uNormalScale
}

void Renderer::setCommonState(const RenderSettings& s) {
    glDisable(GL_BLEND);
    glDisable(GL_SCISSOR_TEST);
    for (int i = 0; i < 4; ++i) glDisable(GL_CLIP_DISTANCE0 + i);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    // Row 0 of every target is the image's top row, so read-backs need no flip. The facing
    // of polygons is unchanged (glClipControl negates the area's sign with the origin).
    glClipControl(GL_UPPER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    glFrontFace(GL_CCW);
    glProvokingVertex(GL_LAST_VERTEX_CONVENTION);
    if (s.cullBackFaces) {
        glEnable(GL_CULL_FACE);
        glCullFace(GL_BACK);
    } else {
        glDisable(GL_CULL_FACE);
    }
    glPolygonMode(GL_FRONT_AND_BACK, s.wireframe ? GL_LINE : GL_FILL);
    glClearColor(s.clearColor.x, s.clearColor.y, s.clearColor.z, 1.0f);
    glClearDepth(1.0);
    glViewport(0, 0, s.width, s.height);
    if (mNormalMaps) {
        // The tangent of a mesh without tangents (its attribute arrays disabled): (0, 0, 0, 1),
        // a degenerate frame (lighting.h perturbedNormal keeps the normal), as the soft backend.
        glVertexAttrib4f(5, 0.0f, 0.0f, 0.0f, 1.0f);
        for (GLuint a = 13; a <= 15; ++a) glVertexAttrib4f(a, 0.0f, 0.0f, 0.0f, 1.0f);
    }
}

void Renderer::drawScene(const Frame& f, GLuint prog, int instances) {
    for (int idx : f.order) {
        const Instance& inst = f.scene->instances[static_cast<std::size_t>(idx)];
        GpuMesh& g = *f.meshes[static_cast<std::size_t>(inst.mesh)];
        setInstanceUniforms(prog, inst);
        setInstanceState(f, inst);
        glBindVertexArray(f.flatProvoking ? g.flatVao.get() : g.vao.get());
        if (instances > 1) {
            glDrawElementsInstanced(GL_TRIANGLES, g.indexCount, GL_UNSIGNED_INT, nullptr,
                                    instances);
        } else {
            glDrawElements(GL_TRIANGLES, g.indexCount, GL_UNSIGNED_INT, nullptr);
        }
    }
    endInstanceState(f);
}

// ---- targets ---------------------------------------------------------------------------------

namespace {
/// A multisampled colour or depth texture of `samples` a pixel with fixed sample locations
/// (every pixel and layer samples the same positions); 2D, or a 2D array of `layers` (> 0).
Texture multisampledTexture(int samples, GLenum format, int w, int h, int layers = 0) {
    Texture t = createTexture(layers > 0 ? GL_TEXTURE_2D_MULTISAMPLE_ARRAY
                                         : GL_TEXTURE_2D_MULTISAMPLE);
    if (layers > 0)
        glTextureStorage3DMultisample(t.get(), samples, format, w, h, layers, GL_TRUE);
    else
        glTextureStorage2DMultisample(t.get(), samples, format, w, h, GL_TRUE);
    return t;
}
}  // namespace

void Renderer::ensureLayered(int w, int h, int layers, int samples) {
    LayeredTarget& t = mGpu->layered;
    if (t.w == w && t.h == h && t.layers == layers && t.samples == samples) return;
    t.color = createTexture(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(t.color.get(), 1, GL_RGBA8, w, h, layers);
    t.depth = createTexture(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(t.depth.get(), 1, GL_DEPTH_COMPONENT32F, w, h, layers);
    t.msColor = {};
    t.msDepth = {};
    if (samples > 1) {
        t.msColor = multisampledTexture(samples, GL_RGBA8, w, h, layers);
        t.msDepth = multisampledTexture(samples, GL_DEPTH_COMPONENT32F, w, h, layers);
    }
    t.fbo = createFramebuffer();
    t.multiviewFbo = createFramebuffer();
    t.resolveFbo = createFramebuffer();
    t.w = w;
    t.h = h;
    t.layers = layers;
    t.samples = samples;
}

void Renderer::ensureMrt(int w, int h, int samples) {
    MrtTarget& t = mGpu->mrt;
    if (t.w == w && t.h == h && t.samples == samples) return;
    t.fbo = createFramebuffer();
    t.resolveFbo = createFramebuffer();
    const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    for (int i = 0; i < 2; ++i) {
        t.color[i] = createTexture(GL_TEXTURE_2D);
        glTextureStorage2D(t.color[i].get(), 1, GL_RGBA8, w, h);
        t.msColor[i] = {};
        if (samples > 1) t.msColor[i] = multisampledTexture(samples, GL_RGBA8, w, h);
        glNamedFramebufferTexture(t.fbo.get(), bufs[i],
                                  samples > 1 ? t.msColor[i].get() : t.color[i].get(), 0);
        glNamedFramebufferTexture(t.resolveFbo.get(), bufs[i], t.color[i].get(), 0);
    }
    glNamedFramebufferDrawBuffers(t.fbo.get(), 2, bufs);
    glNamedFramebufferDrawBuffers(t.resolveFbo.get(), 2, bufs);
    // gs-depthmap's left-eye depth map: one sample (its fragment test reads it per pixel).
    t.depthMap = createTexture(GL_TEXTURE_2D);
    glTextureStorage2D(t.depthMap.get(), 1, GL_DEPTH_COMPONENT32F, w, h);
    t.depthFbo = createFramebuffer();
    glNamedFramebufferTexture(t.depthFbo.get(), GL_DEPTH_ATTACHMENT, t.depthMap.get(), 0);
    glNamedFramebufferDrawBuffer(t.depthFbo.get(), GL_NONE);
    t.w = w;
    t.h = h;
    t.samples = samples;
}

void Renderer::ensureTiled(int w, int h, int samples) {
    // Kept while it holds w × h and is not much larger (passes of fewer views use its top-left
    // corner); remade otherwise.
    TiledTarget& t = mGpu->tiled;
    const double area = double(t.w) * t.h, need = double(w) * h;
    if (t.w >= w && t.h >= h && area <= 4.0 * need && t.samples == samples) return;
    t.color = createTexture(GL_TEXTURE_2D);
    glTextureStorage2D(t.color.get(), 1, GL_RGBA8, w, h);
    t.depth = createTexture(GL_TEXTURE_2D);
    glTextureStorage2D(t.depth.get(), 1, GL_DEPTH_COMPONENT32F, w, h);
    t.msColor = {};
    t.msDepth = {};
    if (samples > 1) {
        t.msColor = multisampledTexture(samples, GL_RGBA8, w, h);
        t.msDepth = multisampledTexture(samples, GL_DEPTH_COMPONENT32F, w, h);
    }
    t.fbo = createFramebuffer();
    glNamedFramebufferTexture(t.fbo.get(), GL_COLOR_ATTACHMENT0,
                              samples > 1 ? t.msColor.get() : t.color.get(), 0);
    glNamedFramebufferTexture(t.fbo.get(), GL_DEPTH_ATTACHMENT,
                              samples > 1 ? t.msDepth.get() : t.depth.get(), 0);
    t.resolveFbo = createFramebuffer();
    glNamedFramebufferTexture(t.resolveFbo.get(), GL_COLOR_ATTACHMENT0, t.color.get(), 0);
    glNamedFramebufferTexture(t.resolveFbo.get(), GL_DEPTH_ATTACHMENT, t.depth.get(), 0);
    t.w = w;
    t.h = h;
    t.samples = samples;
}

// ---- render ----------------------------------------------------------------------------------

Status Renderer::renderInto(const Scene& scene, const Rig& rig, const RenderSettings& s,
                            const std::string& method, RenderOutput& out) {
    // The request first (the same message from every backend, driver or none), then what
    // this driver can do.
    if (Status st = validateRequest(scene, rig, s); !st) return st;
    if (Status st = supports(method); !st) return st;
    const GlMethod& m = *findMethod(method);  // the one look-up of the name
    mNormalMaps = drawsNormalMaps(scene, s);  // before any view limit: the tangent's components
    mEnvironment = scene.environment != nullptr;  // before any program is built
    if (m.measuresExact) return renderAuto(scene, rig, s, out);
    return renderOnce(scene, rig, s, m, out);
}

Status Renderer::renderOnce(const Scene& scene, const Rig& rig, const RenderSettings& s,
                            const GlMethod& method, RenderOutput& out) {
    const auto t0 = Clock::now();
    const int views = rig.viewCount();
    if (Status st = checkViews(method, views, s); !st) return st;
    mVertexColors = false;
    for (const Instance& inst : scene.instances) {
        mVertexColors = mVertexColors || (inst.mesh >= 0 && std::size_t(inst.mesh) < scene.meshes.size() &&
                                          !scene.meshes[std::size_t(inst.mesh)].colors.empty());
    }
    // kalaiah2007 §3: as many views a pass as the method takes, then the next pass.
    Status refused;
    const int limit =
        passLimit(method, s.shading, s.width, s.height, mShadows != nullptr, &refused);
    if (limit < 1) return refused ? internalError("gl: no pass limit") : refused;
    const int perPass = std::min(views, limit);
    const int passes = passCount(views, perPass);
    Frame f;
    f.method = &method;
    f.scene = &scene;
    f.rig = &rig;
    f.settings = &s;
    f.views = views;
    f.targetViews = perPass;
    // --aa N multisampled (GlBackend sends N > 1 here only where multisamples() says so).
    f.samples = s.samples;
    if (f.samples > 1 && !drawsSamples(method, f.samples))
        return internalError(fmt::format("gl: {} does not draw {} samples a pixel here",
                                         method.name, f.samples));
    if (Status st = prepareScene(scene, f, mLastSceneKey); !st) return st;
    if (Status st = prepareEnvironment(scene); !st) return st;
    f.order = drawOrder(scene);
    f.flatProvoking = s.shading == Shading::Flat && method.flatProvoking;

    // out's images are reused where they already have this size (renderInto, frame after frame).
    out.method = method.name;
    out.note = method.artifact ? method.artifact : "";
    out.stages = {};
    out.color.resize(static_cast<std::size_t>(method.target == TargetKind::Mrt ? 2 : views));
    out.depth.resize(
        static_cast<std::size_t>(method.target != TargetKind::Mrt && s.depth ? views : 0));
    // No depth images asked: each view's range instead (RenderOutput::depthRange), reduced on
    // the GPU (readback.cpp), or by startRead() from the depth it reads into scratch memory.
    const bool ranges = !s.depth && method.target != TargetKind::Mrt;
    const bool gpuRanges = ranges && gpuDepthRanges();
    out.depthRange.assign(ranges ? std::size_t(views) : 0, DepthRange{});
    if (gpuRanges) {
        if (Status st = beginDepthRanges(views); !st) return st;
    }
    GlFrameStats stats;
    stats.method = method.name;
    stats.gpuMs = mCaps.timerBits > 0 ? 0.0 : -1.0;
    stats.passes = passes;
    stats.samples = f.samples;
    // A pass's rig: its views, side by side (the whole rig when one pass takes them all).
    Rig passRig;
    if (passes > 1) {
        passRig = rig;
        passRig.columns = perPass;
        passRig.rows = 1;
        passRig.views.resize(static_cast<std::size_t>(perPass));
    }
    // Pass p's pixels travel while pass p + 1 is drawn (hardware drivers; software ones read
    // synchronously, see startRead).
    std::optional<PendingRead> pending;
    auto finish = [&] {
        if (!pending) return;
        const auto tRead = Clock::now();
        finishRead(*pending, out, s);
        stats.readbackWallMs += msSince(tRead);
        pending.reset();
    };
    for (int p = 0; p < passes; ++p) {
        f.firstView = p * perPass;
        f.views = std::min(perPass, views - f.firstView);
        if (passes > 1) {
            const auto first = rig.views.begin() + f.firstView;
            passRig.views.assign(first, first + f.views);
            passRig.columns = f.views;
            f.rig = &passRig;
        }
        if (method.target == TargetKind::Tiled) {
            // Each pass lays out its own views (a pass of k views draws as a rig of k views
            // does, bit for bit) in the top-left corner of one target (ensureTiled).
            auto t = tileLayout(*f.rig, s.width, s.height);
            if (!t) return t.status();
            f.tiles = *t;
        }
        if (Status st = drawPass(f, p, stats); !st) {
            if (pending && pending->fence) glDeleteSync(pending->fence);
            return st;
        }
        const auto tRead = Clock::now();
        if (gpuRanges) {
            if (Status st = reduceDepthRanges(f); !st) {
                if (pending && pending->fence) glDeleteSync(pending->fence);
                return st;
            }
        }
        std::optional<PendingRead> next = startRead(f, out, p);
        stats.readbackWallMs += msSince(tRead);
        finish();
        pending = next;
    }
    finish();
    if (gpuRanges) {
        const auto tRead = Clock::now();
        if (Status st = readDepthRanges(out, views); !st) return st;
        stats.readbackWallMs += msSince(tRead);
    }
    if (Status st = checkGlError("reading back"); !st) return st;
    stats.totalWallMs = msSince(t0);
    if (stats.gpuMs >= 0.0) {
        for (int p = 0; p < passes; ++p) {
            GLuint64 ns = 0;
            glGetQueryObjectui64v(mGpu->timers[std::size_t(p)].get(), GL_QUERY_RESULT, &ns);
            stats.gpuMs += static_cast<double>(ns) * 1e-6;
        }
        // The draws ran within the frame: a longer GPU time is no measurement (llvmpipe's
        // first query reads ~6e6 ms). Not reported then.
        if (stats.gpuMs > stats.totalWallMs + 0.5) stats.gpuMs = -1.0;
    }
    if (!mCaps.softwareRenderer()) {
        // Draws and transfers overlap there: what the CPU spent on the pixels (issuing the
        // reads, mapping, copying) is the read-back; the rest of the frame is the draw.
        stats.drawWallMs = std::max(0.0, stats.totalWallMs - stats.readbackWallMs);
    }
    mLastStats = stats;
    return Status::ok();
}

Status Renderer::drawPass(Frame& f, int pass, GlFrameStats& stats) {
    const GlMethod& method = *f.method;
    const RenderSettings& s = *f.settings;
    ProgramDesc desc = passProgram(method, s.shading, f.views, mShadows != nullptr,
                                   shadesFromEachEye(s));
    if (f.samples > 1) addDefine(desc, "CENTROID");
    Result<GLuint> prog = program(method.name, desc);
    if (!prog) return prog.status();
    if (method.prepare) {
        if (Status st = (this->*method.prepare)(f); !st) return st;
    }
    uploadFrameBlock(f);
    setCommonState(s);
    if (desc.geometry && mLastGeometryProgram && mLastGeometryProgram != *prog) {
        // zink (Mesa 22.3) keeps the viewport count of the last geometry shader while one
        // geometry shader replaces another: viewport-array after gs-layered drew nothing in
        // views 1.. . A draw without a geometry shader in between resets it; this one draws
        // nothing (one point, rasterizer discard).
        Result<GLuint> plain = program(depthPrepassName(), depthPrepassProgram());
        if (!plain) return plain.status();
        glUseProgram(*plain);
        glEnable(GL_RASTERIZER_DISCARD);
        glBindVertexArray(mGpu->emptyVao.get());
        glDrawArrays(GL_POINTS, 0, 1);
        glDisable(GL_RASTERIZER_DISCARD);
    }
    mLastGeometryProgram = desc.geometry ? *prog : 0;
    glUseProgram(*prog);
    if (mShadows) setShadowUniforms(*prog);
    if (mEnvironment) bindEnvironment();
    if (Status st = checkGlError("setting up the frame"); !st) return st;

    const auto tDraw = Clock::now();
    const bool timed = mCaps.timerBits > 0 && stats.gpuMs >= 0.0;
    if (timed) {
        // One query a pass, read when the frame is done (reading one waits for its draw).
        while (mGpu->timers.size() <= std::size_t(pass))
            mGpu->timers.push_back(createQuery(GL_TIME_ELAPSED));
        glBeginQuery(GL_TIME_ELAPSED, mGpu->timers[std::size_t(pass)].get());
    }
    Status drawn = method.draw
                       ? (this->*method.draw)(f, *prog)
                       : internalError(fmt::format("gl: no draw path for {}", method.name));
    if (drawn && f.samples > 1) drawn = resolveSamples(f);
    if (timed) glEndQuery(GL_TIME_ELAPSED);
    // Software rasterisers draw on the CPU: wait, so that the draw's wall time is its own. A
    // GPU keeps drawing while the CPU copies the previous pass's pixels (renderOnce).
    if (mCaps.softwareRenderer()) glFinish();
    stats.drawWallMs += msSince(tDraw);
    if (!drawn) return drawn;
    if (Status st = checkGlError(fmt::format("drawing with {}", method.name).c_str()); !st)
        return st;
    return Status::ok();
}

Status Renderer::renderAuto(const Scene& scene, const Rig& rig, const RenderSettings& s,
                            RenderOutput& out) {
    // Only the exact rows, which give every view its own depth buffer (identical images): the
    // artifact rows (sorbier2008's painter's order) trade correctness for speed, so auto never
    // picks them.
    Frame probe;
    std::uint64_t sceneKey = 0;
    if (Status st = prepareScene(scene, probe, sceneKey); !st) return st;
    const std::string key =
        fmt::format("{:x}/{}x{}/{}/{}/{}{}/{}/{}", sceneKey, s.width, s.height, rig.viewCount(),
                    shadingName(s.shading), s.cullBackFaces, s.wireframe, int(s.specular),
                    s.samples);
    if (auto it = mAutoChoices.find(key); it != mAutoChoices.end()) {
        if (Status st = renderOnce(scene, rig, s, *it->second.method, out); !st) return st;
        out.method = it->second.method->name;
        out.note = it->second.note;
        return Status::ok();
    }
    std::vector<std::pair<double, const GlMethod*>> times;
    std::vector<std::string> skipped;
    for (const GlMethod& m : glMethods()) {
        if (!m.exact()) continue;
        const std::string name = m.name;
        if (s.samples > 1 && !drawsSamples(m, s.samples)) {
            skipped.push_back(name + " (no multisampled target)");
            continue;
        }
        if (Status st = supportsMethod(m); !st) {
            skipped.push_back(name + " (unsupported)");
            continue;
        }
        if (Status st = checkViews(m, rig.viewCount(), s); !st) {
            skipped.push_back(name + " (view limit)");
            continue;
        }
        // One warm-up (compiles, allocates), then the best of two timed renders.
        double ms = 1e300;
        bool failed = false;
        for (int run = 0; run < 3 && !failed; ++run) {
            if (Status st = renderOnce(scene, rig, s, m, out); !st) {
                skipped.push_back(name + " (" + st.message() + ")");
                failed = true;
                break;
            }
            if (run > 0) ms = std::min(ms, mLastStats->totalWallMs);
        }
        if (failed) continue;
        times.emplace_back(ms, &m);
    }
    if (times.empty())
        return unsupportedError("gl: auto: no method can render this here: " +
                                fmt::format("{}", fmt::join(skipped, ", ")));
    // Fastest first; equal times by name.
    std::sort(times.begin(), times.end(), [](const auto& a, const auto& b) {
        return a.first != b.first ? a.first < b.first
                                  : std::string_view(a.second->name) < b.second->name;
    });
    std::vector<std::string> parts;
    for (auto& [ms, m] : times) parts.push_back(fmt::format("{} {:.2f} ms", m->name, ms));
    AutoChoice c;
    c.method = times.front().second;
    const std::string excluded = autoExclusions();
    c.note = fmt::format(
        "auto picked {}: fastest of the exact (per-view depth) methods measured "
        "on {} for {} views at {}x{} ({}){}{}",
        c.method->name, mCaps.renderer, rig.viewCount(), s.width, s.height, fmt::join(parts, ", "),
        excluded.empty() ? "" : "; " + excluded,
        skipped.empty() ? "" : fmt::format("; skipped: {}", fmt::join(skipped, ", ")));
    mAutoChoices[key] = c;
    // The returned images and stats are its.
    if (Status st = renderOnce(scene, rig, s, *c.method, out); !st) return st;
    out.method = c.method->name;
    out.note = c.note;
    return Status::ok();
}

}  // namespace mvr::gl::detail

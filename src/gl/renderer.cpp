#include "renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <string_view>

#include <fmt/format.h>

namespace mvr::gl::detail {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// 64-bit content hash, 8 bytes a step (FNV-style mixing; not cryptographic).
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

std::uint64_t hashMesh(const Mesh& m) {
    std::uint64_t h = 0xCBF29CE484222325ull;
    h = hashBytes(h, m.positions.data(), m.positions.size() * sizeof(glm::vec3));
    h = hashBytes(h, m.normals.data(), m.normals.size() * sizeof(glm::vec3));
    h = hashBytes(h, m.indices.data(), m.indices.size() * sizeof(std::uint32_t));
    h = hashBytes(h, m.texcoords.data(), m.texcoords.size() * sizeof(glm::vec2));
    return h;
}

// Attributes 0 position, 1 normal, 2 texture coordinate, 3 (flat arrays) the face's centroid.
void bindVertexArray(GLuint vao, GLuint positions, GLuint normals, GLuint texcoords, GLuint indices,
                     GLuint centers = 0) {
    glVertexArrayVertexBuffer(vao, 0, positions, 0, sizeof(glm::vec3));
    glVertexArrayVertexBuffer(vao, 1, normals, 0, sizeof(glm::vec3));
    glVertexArrayVertexBuffer(vao, 2, texcoords, 0, sizeof(glm::vec2));
    glVertexArrayElementBuffer(vao, indices);
    for (GLuint a = 0; a < 3; ++a) {
        glEnableVertexArrayAttrib(vao, a);
        glVertexArrayAttribFormat(vao, a, a == 2 ? 2 : 3, GL_FLOAT, GL_FALSE, 0);
        glVertexArrayAttribBinding(vao, a, a);
    }
    if (centers) {
        glVertexArrayVertexBuffer(vao, 3, centers, 0, sizeof(glm::vec3));
        glEnableVertexArrayAttrib(vao, 3);
        glVertexArrayAttribFormat(vao, 3, 3, GL_FLOAT, GL_FALSE, 0);
        glVertexArrayAttribBinding(vao, 3, 3);
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
    if (!mContext || !mContext->makeCurrent()) {
        // Without the context current, GL objects must not be deleted through GL calls:
        // hand the names over (the context, if any, frees them with itself).
        for (auto& [k, m] : mMeshes) {
            m.positions.release();
            m.normals.release();
            m.indices.release();
            m.texcoords.release();
            m.vao.release();
            m.flatTexcoords.release();
            m.flatCenters.release();
            m.kalaiahTexcoords.release();
            m.flatPositions.release();
            m.flatNormals.release();
            m.flatIndices.release();
            m.flatVao.release();
            m.kalaiahTriangles.release();
            m.kalaiahVao.release();
            m.kalaiahDummy.release();
        }
        for (auto& [k, p] : mPrograms) p.release();
        for (auto& [k, t] : mTextures) t.texture.release();
        for (auto& [k, smp] : mSamplers) smp.release();
        mFrameUbo.release();
        mTimer.release();
        mEmptyVao.release();
        mLayered.color.release();
        mLayered.depth.release();
        mLayered.fbo.release();
        for (auto& t : mMrt.color) t.release();
        mMrt.depthMap.release();
        mMrt.fbo.release();
        mMrt.depthFbo.release();
        mTiled.color.release();
        mTiled.depth.release();
        mTiled.fbo.release();
        return;
    }
    mMeshes.clear();
    mTextures.clear();
    mSamplers.clear();
    mPrograms.clear();
    mFrameUbo.reset();
    mTimer.reset();
    mEmptyVao.reset();
    mLayered = {};
    mTiled = {};
    for (auto& t : mMrt.color) t.reset();
    mMrt.depthMap.reset();
    mMrt.fbo.reset();
    mMrt.depthFbo.reset();
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
    mFrameUbo = createBuffer();
    glNamedBufferStorage(mFrameUbo.get(), sizeof(FrameBlock), nullptr, GL_DYNAMIC_STORAGE_BIT);
    if (mCaps.timerBits > 0) mTimer = createQuery(GL_TIME_ELAPSED);
    mEmptyVao = createVertexArray();
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
    for (const GlMethod& m : glMethods()) {
        if (m.measuresExact) continue;
        if (const std::string why = m.missing ? m.missing(mCaps) : ""; !why.empty()) {
            lines.push_back(fmt::format("method {}: unsupported: {}", m.name, why));
            continue;
        }
        const int lf = viewLimit(m, Shading::Flat, 1024, 768);
        const int lp = viewLimit(m, Shading::Pixel, 1024, 768);
        if (m.fixedViews > 0 || std::min(lf, lp) >= kMaxViews) {
            lines.push_back(fmt::format("method {}: supported, up to {} views", m.name, lf));
        } else if (lf == lp) {
            lines.push_back(
                fmt::format("method {}: supported, {} views per pass, batches beyond", m.name, lf));
        } else {
            lines.push_back(
                fmt::format("method {}: supported, {} views per pass (flat/vertex), "
                            "{} (pixel) at 1024x768, batches beyond",
                            m.name, lf, lp));
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
    return detail::viewLimit(m, mCaps, shading, width, height);
}

Status Renderer::checkViews(const GlMethod& m, int views, const RenderSettings& s) const {
    // Colour (4 bytes) + depth (4 bytes) per pixel per view on the GPU side, the same again
    // for the images handed back: refuse what would not fit in memory instead of failing
    // (or being killed) halfway.
    constexpr double kBudgetBytes = 4.0 * 1024 * 1024 * 1024;
    const double bytes = 8.0 * s.width * s.height * views;
    if (bytes > kBudgetBytes) {
        return unsupportedError(fmt::format(
            "gl: {} views of {}x{} need {:.1f} GiB of colour + depth targets (limit {:.0f} GiB)",
            views, s.width, s.height, bytes / (1024.0 * 1024 * 1024),
            kBudgetBytes / (1024.0 * 1024 * 1024)));
    }
    return checkMethodViews(m, mCaps, views, s);
}

Status Renderer::prepareScene(const Scene& scene, Frame& frame, std::uint64_t& sceneKey) {
    ++mUseCounter;
    sceneKey = 0x9E3779B97F4A7C15ull;
    frame.meshes.assign(scene.meshes.size(), nullptr);
    for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
        const Mesh& src = scene.meshes[i];
        const std::uint64_t key = hashMesh(src);
        sceneKey = (sceneKey ^ key) * 0x100000001B3ull;
        auto it = mMeshes.find(key);
        if (it == mMeshes.end()) {
            // Keep a few meshes; drop the least recently used beyond that.
            while (mMeshes.size() >= 32) {
                auto lru = std::min_element(mMeshes.begin(), mMeshes.end(), [](auto& a, auto& b) {
                    return a.second.lastUse < b.second.lastUse;
                });
                mMeshes.erase(lru);
            }
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
            g.vao = createVertexArray();
            bindVertexArray(g.vao.get(), g.positions.get(), g.normals.get(), g.texcoords.get(),
                            g.indices.get());

            // Provoking-vertex arrays for flat shading: rotate each triangle (keeping its
            // winding) so that its last vertex is one no earlier triangle used as provoking
            // vertex; duplicate a vertex when all three are taken.
            std::vector<glm::vec3> pos = src.positions;
            std::vector<glm::vec3> face(pos.size(), glm::vec3(0.0f));
            std::vector<glm::vec2> flatUv = uv;
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
            g.flatVao = createVertexArray();
            bindVertexArray(g.flatVao.get(), g.flatPositions.get(), g.flatNormals.get(),
                            g.flatTexcoords.get(), g.flatIndices.get(), g.flatCenters.get());
            if (Status s = checkGlError("uploading a mesh"); !s) return s;
            it = mMeshes.emplace(key, std::move(g)).first;
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
        if (tiles) {
            // ndc' = (ndc + 1) / C + 2c / C − 1, i.e. clip.x' = clip.x / C + clip.w ((1 + 2c) / C − 1).
            const glm::ivec2 o = tiles->origin(v);
            const float cx = static_cast<float>(o.x / tiles->width);
            const float cy = static_cast<float>(o.y / tiles->height);
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
    b.ambient = glm::vec4(f.scene->ambient, 0.0f);
    b.centerEye = glm::vec4(f.rig->centerEye(), 1.0f);
    b.counts = {static_cast<int>(std::min<std::size_t>(lights.size(), kMaxLights)), f.views,
                f.settings->width, f.settings->height};
    glNamedBufferSubData(mFrameUbo.get(), 0, sizeof(FrameBlock), &b);
    glBindBufferBase(GL_UNIFORM_BUFFER, 0, mFrameUbo.get());
}

Result<GLuint> Renderer::program(const std::string& label, const ProgramDesc& d) {
    const std::string key = d.vsExtensions + d.defines + (d.geometry ? "GS" : "");
    if (auto it = mPrograms.find(key); it != mPrograms.end()) return it->second.get();
    if (auto it = mProgramErrors.find(key); it != mProgramErrors.end()) return it->second;
    auto p = buildProgram(d);
    if (!p) {
        Status s(p.status().code(), fmt::format("gl: {}: {}", label, p.status().message()));
        mProgramErrors.emplace(key, s);
        return s;
    }
    const GLuint name = p->get();
    mPrograms.emplace(key, std::move(p).value());
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
    glProgramUniform4i(prog, 6, mat.baseColorTexture >= 0 ? 1 : 0, mode, mat.doubleSided ? 1 : 0,
                       0);
    glProgramUniform2f(prog, 7, mat.alpha, mat.alphaCutoff);
}

void Renderer::setCommonState(const RenderSettings& s) {
    glDisable(GL_BLEND);
    glDisable(GL_SCISSOR_TEST);
    for (int i = 0; i < 4; ++i) glDisable(GL_CLIP_DISTANCE0 + i);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
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

void Renderer::ensureLayered(int w, int h, int layers) {
    if (mLayered.w == w && mLayered.h == h && mLayered.layers == layers) return;
    mLayered.color = createTexture(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(mLayered.color.get(), 1, GL_RGBA8, w, h, layers);
    mLayered.depth = createTexture(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(mLayered.depth.get(), 1, GL_DEPTH_COMPONENT32F, w, h, layers);
    mLayered.fbo = createFramebuffer();
    mLayered.w = w;
    mLayered.h = h;
    mLayered.layers = layers;
}

void Renderer::ensureMrt(int w, int h) {
    if (mMrt.w == w && mMrt.h == h) return;
    mMrt.fbo = createFramebuffer();
    for (int i = 0; i < 2; ++i) {
        mMrt.color[i] = createTexture(GL_TEXTURE_2D);
        glTextureStorage2D(mMrt.color[i].get(), 1, GL_RGBA8, w, h);
        glNamedFramebufferTexture(mMrt.fbo.get(), GL_COLOR_ATTACHMENT0 + i, mMrt.color[i].get(), 0);
    }
    const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glNamedFramebufferDrawBuffers(mMrt.fbo.get(), 2, bufs);
    mMrt.depthMap = createTexture(GL_TEXTURE_2D);
    glTextureStorage2D(mMrt.depthMap.get(), 1, GL_DEPTH_COMPONENT32F, w, h);
    mMrt.depthFbo = createFramebuffer();
    glNamedFramebufferTexture(mMrt.depthFbo.get(), GL_DEPTH_ATTACHMENT, mMrt.depthMap.get(), 0);
    glNamedFramebufferDrawBuffer(mMrt.depthFbo.get(), GL_NONE);
    mMrt.w = w;
    mMrt.h = h;
}

void Renderer::ensureTiled(int w, int h) {
    if (mTiled.w == w && mTiled.h == h) return;
    mTiled.color = createTexture(GL_TEXTURE_2D);
    glTextureStorage2D(mTiled.color.get(), 1, GL_RGBA8, w, h);
    mTiled.depth = createTexture(GL_TEXTURE_2D);
    glTextureStorage2D(mTiled.depth.get(), 1, GL_DEPTH_COMPONENT32F, w, h);
    mTiled.fbo = createFramebuffer();
    glNamedFramebufferTexture(mTiled.fbo.get(), GL_COLOR_ATTACHMENT0, mTiled.color.get(), 0);
    glNamedFramebufferTexture(mTiled.fbo.get(), GL_DEPTH_ATTACHMENT, mTiled.depth.get(), 0);
    mTiled.w = w;
    mTiled.h = h;
}

namespace {

// The caller's memory for view `view` of `views` (RenderSettings::output), or nullptr (heap).
OutputBlock* blockFor(const RenderSettings& s, std::size_t views, int w, int h) {
    OutputBlock* b = s.output;
    return b && std::size_t(b->views()) == views && b->width() == w && b->height() == h ? b
                                                                                        : nullptr;
}
std::pmr::memory_resource* colorMemory(OutputBlock* b, std::size_t view) {
    return b ? b->colorMemory(int(view)) : nullptr;
}
std::pmr::memory_resource* depthMemory(OutputBlock* b, std::size_t view) {
    return b ? b->depthMemory(int(view)) : nullptr;
}

// Reads a w×h region of one layer, flipping rows (GL row 0 = bottom, image row 0 = top), into
// an image allocated from `memory` (nullptr: the heap).
void readRegion(GLuint tex, int x, int y, int layer, int w, int h, Image& img,
                std::pmr::memory_resource* memory) {
    img.reset(w, h, memory);
    std::vector<std::uint8_t> tmp(static_cast<std::size_t>(w) * h * 4);
    glGetTextureSubImage(tex, 0, x, y, layer, w, h, 1, GL_RGBA, GL_UNSIGNED_BYTE,
                         static_cast<GLsizei>(tmp.size()), tmp.data());
    const std::size_t row = static_cast<std::size_t>(w) * 4;
    for (int r = 0; r < h; ++r) {
        std::memcpy(img.row(r), tmp.data() + static_cast<std::size_t>(h - 1 - r) * row, row);
    }
}

void readDepthRegion(GLuint tex, int x, int y, int layer, int w, int h, DepthImage& img,
                     std::pmr::memory_resource* memory) {
    img.reset(w, h, 1.0f, memory);
    std::vector<float> tmp(static_cast<std::size_t>(w) * h);
    glGetTextureSubImage(tex, 0, x, y, layer, w, h, 1, GL_DEPTH_COMPONENT, GL_FLOAT,
                         static_cast<GLsizei>(tmp.size() * sizeof(float)), tmp.data());
    for (int r = 0; r < h; ++r) {
        std::memcpy(img.depth.data() + static_cast<std::size_t>(r) * w,
                    tmp.data() + static_cast<std::size_t>(h - 1 - r) * w, w * sizeof(float));
    }
}

}  // namespace

void Renderer::readLayered(RenderOutput& out, const Frame& f, bool depth) {
    const int w = f.settings->width, h = f.settings->height;
    OutputBlock* block = blockFor(*f.settings, out.color.size(), w, h);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    for (int v = 0; v < f.views; ++v) {
        const auto i = static_cast<std::size_t>(f.firstView + v);
        readRegion(mLayered.color.get(), 0, 0, v, w, h, out.color[i], colorMemory(block, i));
        if (depth)
            readDepthRegion(mLayered.depth.get(), 0, 0, v, w, h, out.depth[i],
                            depthMemory(block, i));
    }
}

void Renderer::readTiled(RenderOutput& out, const Frame& f) {
    const TileLayout& t = *f.tiles;
    OutputBlock* block = blockFor(*f.settings, out.color.size(), t.width, t.height);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    for (int v = 0; v < f.views; ++v) {
        const glm::ivec2 o = t.origin(v);
        const auto i = static_cast<std::size_t>(f.firstView + v);
        readRegion(mTiled.color.get(), o.x, o.y, 0, t.width, t.height, out.color[i],
                   colorMemory(block, i));
        readDepthRegion(mTiled.depth.get(), o.x, o.y, 0, t.width, t.height, out.depth[i],
                        depthMemory(block, i));
    }
}

void Renderer::readMrt(RenderOutput& out, const Frame& f) {
    out.color.resize(2);
    OutputBlock* block = blockFor(*f.settings, 2, f.settings->width, f.settings->height);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    for (int v = 0; v < 2; ++v) {
        readRegion(mMrt.color[v].get(), 0, 0, 0, f.settings->width, f.settings->height,
                   out.color[static_cast<std::size_t>(v)], colorMemory(block, std::size_t(v)));
    }
}

// ---- render ----------------------------------------------------------------------------------

Result<RenderOutput> Renderer::render(const Scene& scene, const Rig& rig, const RenderSettings& s,
                                      const std::string& method) {
    // The request first (the same message from every backend, driver or none), then what
    // this driver can do.
    if (Status st = validateRequest(scene, rig, s); !st) return st;
    if (Status st = supports(method); !st) return st;
    const GlMethod& m = *findMethod(method);  // the one look-up of the name
    if (m.measuresExact) return renderAuto(scene, rig, s);
    return renderOnce(scene, rig, s, m);
}

Result<RenderOutput> Renderer::renderOnce(const Scene& scene, const Rig& rig,
                                          const RenderSettings& s, const GlMethod& method) {
    const auto t0 = Clock::now();
    const int views = rig.viewCount();
    if (Status st = checkViews(method, views, s); !st) return st;
    // kalaiah2007 §3: as many views a pass as the method takes, then the next pass.
    const int perPass = std::min(views, viewLimit(method, s.shading, s.width, s.height));
    const int passes = passCount(views, perPass);
    Frame f;
    f.method = &method;
    f.scene = &scene;
    f.rig = &rig;
    f.settings = &s;
    f.views = views;
    f.targetViews = perPass;
    if (Status st = prepareScene(scene, f, mLastSceneKey); !st) return st;
    f.order = drawOrder(scene);
    f.flatProvoking = s.shading == Shading::Flat && method.flatProvoking;

    RenderOutput out;
    out.method = method.name;
    if (method.artifact) out.note = method.artifact;
    if (method.target != TargetKind::Mrt) {
        out.color.resize(static_cast<std::size_t>(views));
        out.depth.resize(static_cast<std::size_t>(views));
    }
    GlFrameStats stats;
    stats.method = method.name;
    stats.gpuMs = mTimer ? 0.0 : -1.0;
    stats.passes = passes;
    // A pass's rig: its views, side by side (the whole rig when one pass takes them all).
    Rig passRig;
    if (passes > 1) {
        passRig = rig;
        passRig.columns = perPass;
        passRig.rows = 1;
        passRig.views.resize(static_cast<std::size_t>(perPass));
    }
    const Rig& layoutRig = passes > 1 ? passRig : rig;
    if (method.target == TargetKind::Tiled) {
        // One layout (of the largest pass) for every pass: the target is made once.
        auto t = tileLayout(layoutRig, s.width, s.height);
        if (!t) return t.status();
        f.tiles = *t;
    }
    for (int p = 0; p < passes; ++p) {
        f.firstView = p * perPass;
        f.views = std::min(perPass, views - f.firstView);
        if (passes > 1) {
            const auto first = rig.views.begin() + f.firstView;
            passRig.views.assign(first, first + f.views);
            passRig.columns = f.views;
            f.rig = &passRig;
        }
        if (Status st = drawPass(f, out, stats); !st) return st;
    }
    stats.totalWallMs = msSince(t0);
    mLastStats = stats;
    return out;
}

Status Renderer::drawPass(Frame& f, RenderOutput& out, GlFrameStats& stats) {
    const GlMethod& method = *f.method;
    const RenderSettings& s = *f.settings;
    ProgramDesc desc = methodProgram(method, mCaps, s.shading, f.views);
    if (mShadows) addDefine(desc, "SHADOWS");  // issue 15: shadow_maps.cpp
    Result<GLuint> prog = program(method.name, desc);
    if (!prog) return prog.status();
    if (method.prepare) {
        if (Status st = (this->*method.prepare)(f); !st) return st;
    }
    uploadFrameBlock(f);
    setCommonState(s);
    glUseProgram(*prog);
    if (mShadows) setShadowUniforms(*prog);
    if (Status st = checkGlError("setting up the frame"); !st) return st;

    const auto tDraw = Clock::now();
    if (mTimer) glBeginQuery(GL_TIME_ELAPSED, mTimer.get());
    const Status drawn = method.draw
                             ? (this->*method.draw)(f, *prog)
                             : internalError(fmt::format("gl: no draw path for {}", method.name));
    if (mTimer) glEndQuery(GL_TIME_ELAPSED);
    glFinish();
    stats.drawWallMs += msSince(tDraw);
    if (!drawn) return drawn;
    if (Status st = checkGlError(fmt::format("drawing with {}", method.name).c_str()); !st)
        return st;

    const auto tRead = Clock::now();
    switch (method.target) {
        case TargetKind::Mrt: readMrt(out, f); break;
        case TargetKind::Tiled: readTiled(out, f); break;
        case TargetKind::Layered: readLayered(out, f, true); break;
    }
    if (Status st = checkGlError("reading back"); !st) return st;
    stats.readbackWallMs += msSince(tRead);
    if (mTimer) {
        GLuint64 ns = 0;
        glGetQueryObjectui64v(mTimer.get(), GL_QUERY_RESULT, &ns);
        stats.gpuMs += static_cast<double>(ns) * 1e-6;
    }
    return Status::ok();
}

Result<RenderOutput> Renderer::renderAuto(const Scene& scene, const Rig& rig,
                                          const RenderSettings& s) {
    // Only the exact rows, which give every view its own depth buffer (identical images): the
    // artifact rows (sorbier2008's painter's order) trade correctness for speed, so auto never
    // picks them.
    Frame probe;
    std::uint64_t sceneKey = 0;
    if (Status st = prepareScene(scene, probe, sceneKey); !st) return st;
    const std::string key =
        fmt::format("{:x}/{}x{}/{}/{}/{}{}", sceneKey, s.width, s.height, rig.viewCount(),
                    shadingName(s.shading), s.cullBackFaces, s.wireframe);
    if (auto it = mAutoChoices.find(key); it != mAutoChoices.end()) {
        auto r = renderOnce(scene, rig, s, *it->second.method);
        if (!r) return r;
        r->method = it->second.method->name;
        r->note = it->second.note;
        return r;
    }
    std::vector<std::pair<double, const GlMethod*>> times;
    std::vector<std::string> skipped;
    for (const GlMethod& m : glMethods()) {
        if (!m.exact()) continue;
        const std::string name = m.name;
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
            auto r = renderOnce(scene, rig, s, m);
            if (!r) {
                skipped.push_back(name + " (" + r.status().message() + ")");
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
    auto r = renderOnce(scene, rig, s, *c.method);  // the returned images and stats are its
    if (!r) return r;
    r->method = c.method->name;
    r->note = c.note;
    return r;
}

}  // namespace mvr::gl::detail

#include "renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

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
    return h;
}

void bindVertexArray(GLuint vao, GLuint positions, GLuint normals, GLuint indices) {
    glVertexArrayVertexBuffer(vao, 0, positions, 0, sizeof(glm::vec3));
    glVertexArrayVertexBuffer(vao, 1, normals, 0, sizeof(glm::vec3));
    glVertexArrayElementBuffer(vao, indices);
    for (GLuint a = 0; a < 2; ++a) {
        glEnableVertexArrayAttrib(vao, a);
        glVertexArrayAttribFormat(vao, a, 3, GL_FLOAT, GL_FALSE, 0);
        glVertexArrayAttribBinding(vao, a, a);
    }
}

const char* shadingDefine(Shading s) {
    switch (s) {
    case Shading::Flat: return "SHADING_FLAT";
    case Shading::Vertex: return "SHADING_VERTEX";
    case Shading::Pixel: return "SHADING_PIXEL";
    }
    return "SHADING_VERTEX";
}

// Components a GS emits per vertex: gl_Position, the layer/viewport/flag, the varyings.
int gsComponentsPerVertex(Shading s, bool depthMap) {
    const int varyings = s == Shading::Pixel ? 6 : 3;
    return 4 + 1 + varyings + (depthMap ? 4 : 0);
}

bool isGsLoop(const std::string& m) {
    return m == "gs-layered" || m == "viewport-array" || m == "gs-mrt" || m == "gs-depthmap";
}
bool isLayered(const std::string& m) {
    return m == "multipass" || m == "gs-layered" || m == "gs-invocations" ||
           m == "instanced-layer" || m == "multiview";
}

}  // namespace

const std::vector<std::string>& methodNames() {
    static const std::vector<std::string> kNames = {
        "multipass",       "gs-mrt",         "gs-depthmap", "gs-layered",        "gs-invocations",
        "instanced-layer", "viewport-array", "multiview",   "kalaiah-emulation", "auto"};
    return kNames;
}

Renderer::~Renderer() {
    if (!mContext || !mContext->makeCurrent()) {
        // Without the context current, GL objects must not be deleted through GL calls:
        // hand the names over (the context, if any, frees them with itself).
        for (auto& [k, m] : mMeshes) {
            m.positions.release(); m.normals.release(); m.indices.release();
            m.vao.release(); m.flatPositions.release(); m.flatNormals.release();
            m.flatIndices.release(); m.flatVao.release();
            m.kalaiahTriangles.release(); m.kalaiahVao.release(); m.kalaiahDummy.release();
        }
        for (auto& [k, p] : mPrograms) p.release();
        mFrameUbo.release(); mTimer.release(); mEmptyVao.release();
        mLayered.color.release(); mLayered.depth.release(); mLayered.fbo.release();
        for (auto& t : mMrt.color) t.release();
        mMrt.depthMap.release(); mMrt.fbo.release(); mMrt.depthFbo.release();
        mTiled.color.release(); mTiled.depth.release(); mTiled.fbo.release();
        return;
    }
    mMeshes.clear();
    mPrograms.clear();
    mFrameUbo.reset(); mTimer.reset(); mEmptyVao.reset();
    mLayered = {}; mTiled = {};
    for (auto& t : mMrt.color) t.reset();
    mMrt.depthMap.reset(); mMrt.fbo.reset(); mMrt.depthFbo.reset();
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
        mContextStatus = unsupportedError(fmt::format(
            "mvr::gl: GL_MAX_UNIFORM_BLOCK_SIZE = {} is below the {} bytes mvr needs",
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
    for (const std::string& m : methodNames()) {
        if (m == "auto") continue;
        Status s = supports(m);
        if (!s) {
            std::string why = s.message();
            if (why.rfind(m + ": ", 0) == 0) why.erase(0, m.size() + 2);
            lines.push_back(fmt::format("method {}: unsupported: {}", m, why));
            continue;
        }
        const int lf = viewLimit(m, Shading::Flat, 1024, 768);
        const int lp = viewLimit(m, Shading::Pixel, 1024, 768);
        lines.push_back(lf == lp ? fmt::format("method {}: supported, up to {} views", m, lf)
                                 : fmt::format("method {}: supported, up to {} views (flat/vertex), "
                                               "{} (pixel) at 1024x768", m, lf, lp));
    }
    return lines;
}

Status Renderer::supports(const std::string& method) {
    if (std::find(methodNames().begin(), methodNames().end(), method) == methodNames().end()) {
        return usageError(fmt::format("gl: unknown method '{}' (expected one of: {})", method,
                                      fmt::join(methodNames(), ", ")));
    }
    if (Status s = ensureContext(); !s) return s;
    const std::string driver = fmt::format("{} ({})", mCaps.renderer, mCaps.version);
    if (method == "instanced-layer" && !mCaps.vertexLayer()) {
        return unsupportedError(fmt::format(
            "instanced-layer: needs GL_ARB_shader_viewport_layer_array or "
            "GL_AMD_vertex_shader_layer (gl_Layer from the vertex shader); {} has neither",
            driver));
    }
    if (method == "multiview" && !mCaps.has("GL_OVR_multiview")) {
        return unsupportedError(fmt::format(
            "multiview: GL_OVR_multiview is not supported by {}", driver));
    }
    if ((method == "gs-mrt" || method == "gs-depthmap") && mCaps.maxDrawBuffers < 2) {
        return unsupportedError(fmt::format("{}: needs 2 draw buffers, GL_MAX_DRAW_BUFFERS = {}",
                                            method, mCaps.maxDrawBuffers));
    }
    if (method == "viewport-array" && mCaps.maxViewports < 2) {
        return unsupportedError(fmt::format("viewport-array: GL_MAX_VIEWPORTS = {}",
                                            mCaps.maxViewports));
    }
    if (method == "kalaiah-emulation" && mCaps.maxClipDistances < 4) {
        return unsupportedError(fmt::format("kalaiah-emulation: needs 4 clip distances, "
                                            "GL_MAX_CLIP_DISTANCES = {}", mCaps.maxClipDistances));
    }
    return Status::ok();
}

Result<TileLayout> Renderer::tileLayout(const Rig& rig, int width, int height,
                                        int maxViewports) const {
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
        return unsupportedError(fmt::format(
            "{} views of {}x{} do not fit in one target of at most {}x{} "
            "(GL_MAX_TEXTURE_SIZE / GL_MAX_VIEWPORT_DIMS)", n, width, height, maxW, maxH));
    }
    (void)maxViewports;
    return t;
}

int Renderer::viewLimit(const std::string& m, Shading shading, int width, int height) const {
    int limit = kMaxViews;
    if (m == "gs-mrt" || m == "gs-depthmap") return 2;
    if (isLayered(m)) limit = std::min({limit, mCaps.maxArrayLayers, mCaps.maxFramebufferLayers});
    if (isGsLoop(m) || m == "gs-invocations") {
        const int comps = gsComponentsPerVertex(shading, m == "gs-depthmap");
        if (m == "gs-invocations") {
            limit = std::min(limit, mCaps.maxGsInvocations);
            if (3 * comps > mCaps.maxGsTotalOutputComponents) limit = 0;
        } else {
            limit = std::min({limit, mCaps.maxGsOutputVertices / 3,
                              mCaps.maxGsTotalOutputComponents / (3 * comps)});
        }
    }
    if (m == "viewport-array") limit = std::min(limit, mCaps.maxViewports);
    if (m == "multiview") limit = std::min(limit, mCaps.maxViewsOvr);
    if (m == "viewport-array" || m == "kalaiah-emulation") {
        const int maxW = std::min(mCaps.maxTextureSize, mCaps.maxViewportDims[0]);
        const int maxH = std::min(mCaps.maxTextureSize, mCaps.maxViewportDims[1]);
        const long tiles = static_cast<long>(maxW / std::max(width, 1)) * (maxH / std::max(height, 1));
        limit = static_cast<int>(std::min<long>(limit, tiles));
    }
    return std::max(limit, 0);
}

Status Renderer::checkViews(const std::string& m, int views, const RenderSettings& s) const {
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
    if ((m == "gs-mrt" || m == "gs-depthmap") && views != 2) {
        return usageError(fmt::format(
            "gl: {} renders exactly 2 views (sorbier2008's stereo pair: one MRT attachment per "
            "eye); the rig has {}", m, views));
    }
    const int limit = viewLimit(m, s.shading, s.width, s.height);
    if (views <= limit) return Status::ok();
    std::string why;
    const int comps = gsComponentsPerVertex(s.shading, m == "gs-depthmap");
    if (isLayered(m) && views > std::min(mCaps.maxArrayLayers, mCaps.maxFramebufferLayers)) {
        why = fmt::format("GL_MAX_ARRAY_TEXTURE_LAYERS = {}, GL_MAX_FRAMEBUFFER_LAYERS = {}",
                          mCaps.maxArrayLayers, mCaps.maxFramebufferLayers);
    } else if (m == "gs-invocations") {
        why = fmt::format("GL_MAX_GEOMETRY_SHADER_INVOCATIONS = {}", mCaps.maxGsInvocations);
    } else if (m == "viewport-array" && views > mCaps.maxViewports) {
        why = fmt::format("GL_MAX_VIEWPORTS = {}", mCaps.maxViewports);
    } else if (isGsLoop(m)) {
        why = fmt::format("the geometry shader emits 3 vertices x {} components per view: "
                          "GL_MAX_GEOMETRY_OUTPUT_VERTICES = {}, "
                          "GL_MAX_GEOMETRY_TOTAL_OUTPUT_COMPONENTS = {}",
                          comps, mCaps.maxGsOutputVertices, mCaps.maxGsTotalOutputComponents);
    } else if (m == "multiview") {
        why = fmt::format("GL_MAX_VIEWS_OVR = {}", mCaps.maxViewsOvr);
    } else if (views > kMaxViews) {
        why = fmt::format("mvr::kMaxViews = {}", kMaxViews);
    } else {
        why = fmt::format("the views' tiles must fit GL_MAX_TEXTURE_SIZE = {}",
                          mCaps.maxTextureSize);
    }
    return unsupportedError(fmt::format("gl: {}: {} views exceed its limit of {} here ({})", m,
                                        views, limit, why));
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
            g.vao = createVertexArray();
            bindVertexArray(g.vao.get(), g.positions.get(), g.normals.get(), g.indices.get());

            // Provoking-vertex arrays for flat shading: rotate each triangle (keeping its
            // winding) so that its last vertex is one no earlier triangle used as provoking
            // vertex; duplicate a vertex when all three are taken.
            std::vector<glm::vec3> pos = src.positions;
            std::vector<glm::vec3> face(pos.size(), glm::vec3(0.0f));
            std::vector<char> used(pos.size(), 0);
            std::vector<std::uint32_t> idx(src.indices.size());
            for (std::size_t t = 0; t < src.triangleCount(); ++t) {
                std::uint32_t v[3] = {src.indices[3 * t], src.indices[3 * t + 1],
                                      src.indices[3 * t + 2]};
                const glm::vec3 n = glm::cross(src.positions[v[1]] - src.positions[v[0]],
                                               src.positions[v[2]] - src.positions[v[0]]);
                int pick = !used[v[2]] ? 2 : !used[v[0]] ? 0 : !used[v[1]] ? 1 : -1;
                if (pick < 0) {
                    v[2] = static_cast<std::uint32_t>(pos.size());
                    pos.push_back(src.positions[src.indices[3 * t + 2]]);
                    face.emplace_back(0.0f);
                    used.push_back(0);
                    pick = 2;
                }
                const std::uint32_t r[3] = {v[(pick + 1) % 3], v[(pick + 2) % 3], v[pick]};
                used[r[2]] = 1;
                face[r[2]] = n;
                std::copy(r, r + 3, idx.begin() + static_cast<std::ptrdiff_t>(3 * t));
            }
            g.flatPositions = createBuffer();
            g.flatNormals = createBuffer();
            g.flatIndices = createBuffer();
            glNamedBufferStorage(g.flatPositions.get(), pos.size() * sizeof(glm::vec3), pos.data(), 0);
            glNamedBufferStorage(g.flatNormals.get(), face.size() * sizeof(glm::vec3), face.data(), 0);
            glNamedBufferStorage(g.flatIndices.get(), idx.size() * sizeof(std::uint32_t), idx.data(), 0);
            g.flatVao = createVertexArray();
            bindVertexArray(g.flatVao.get(), g.flatPositions.get(), g.flatNormals.get(),
                            g.flatIndices.get());
            if (Status s = checkGlError("uploading a mesh"); !s) return s;
            it = mMeshes.emplace(key, std::move(g)).first;
        }
        it->second.lastUse = mUseCounter;
        frame.meshes[i] = &it->second;
    }
    sceneKey ^= scene.instances.size() * 0x9E3779B1ull;
    return Status::ok();
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
        glNamedBufferStorage(g.kalaiahTriangles.get(), data.size() * sizeof(glm::vec3),
                             data.data(), 0);
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
        glEnableVertexArrayAttrib(vao, 0);
        glVertexArrayAttribIFormat(vao, 0, 2, GL_INT, 0);
        glVertexArrayAttribBinding(vao, 0, 0);
    }
    if (g.kalaiahViews != views) {
        // V dummy triangles: vertex i of triangle j is (i, j).
        std::vector<glm::ivec2> dummy;
        for (int j = 0; j < views; ++j)
            for (int i = 0; i < 3; ++i) dummy.emplace_back(i, j);
        g.kalaiahDummy = createBuffer();
        glNamedBufferStorage(g.kalaiahDummy.get(), dummy.size() * sizeof(glm::ivec2),
                             dummy.data(), 0);
        glVertexArrayVertexBuffer(g.kalaiahVao.get(), 0, g.kalaiahDummy.get(), 0,
                                  sizeof(glm::ivec2));
        g.kalaiahViews = views;
    }
    return checkGlError("uploading the kalaiah2007 arrays");
}

void Renderer::uploadFrameBlock(const Frame& f, const TileLayout* tiles) {
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
    for (std::size_t i = 0; i < lights.size() && i < 4; ++i) {
        b.lightDir[i] = glm::vec4(lights[i].towardLight, 0.0f);
        b.lightColor[i] = glm::vec4(lights[i].color, 0.0f);
    }
    b.ambient = glm::vec4(f.scene->ambient, 0.0f);
    b.centerEye = glm::vec4(f.rig->centerEye(), 1.0f);
    b.counts = {static_cast<int>(std::min<std::size_t>(lights.size(), 4)), f.views,
                f.settings->width, f.settings->height};
    glNamedBufferSubData(mFrameUbo.get(), 0, sizeof(FrameBlock), &b);
    glBindBufferBase(GL_UNIFORM_BUFFER, 0, mFrameUbo.get());
}

Result<GLuint> Renderer::program(const std::string& method, const Frame& f) {
    const int n = f.views;
    ProgramDesc d;
    std::string& defs = d.defines;
    auto def = [&](const std::string& name, int value = 1) {
        defs += fmt::format("#define {} {}\n", name, value);
    };
    const Shading shading = f.settings->shading;
    if (method == "depth-prepass") {
        def("DEPTH_ONLY");
        def("VS_DIRECT");
    } else {
        def(shadingDefine(shading));
    }
    const bool flat = shading == Shading::Flat;
    if (method == "multipass") {
        def("VS_DIRECT");
        if (flat) def("FLAT_PROVOKING");
    } else if (method == "gs-layered" || method == "viewport-array" || method == "gs-mrt" ||
               method == "gs-depthmap") {
        def("VS_TO_GS");
        def("GS_VIEWS", n);
        def("GS_MAX_VERTICES", 3 * n);
        def(method == "gs-layered" ? "GS_OUT_LAYER"
            : method == "viewport-array" ? "GS_OUT_VIEWPORT" : "GS_OUT_FLAG");
        if (method == "gs-depthmap") def("DEPTHMAP");
        d.geometry = true;
    } else if (method == "gs-invocations") {
        def("VS_TO_GS");
        def("GS_INVOCATIONS", n);
        def("GS_OUT_LAYER");
        d.geometry = true;
    } else if (method == "instanced-layer") {
        def("VS_INSTANCED_LAYER");
        if (flat) def("FLAT_PROVOKING");
        d.vsExtensions = fmt::format("#extension {} : require\n", mCaps.vertexLayerExtension());
    } else if (method == "multiview") {
        def("VS_MULTIVIEW");
        def("NUM_VIEWS", n);
        if (flat) def("FLAT_PROVOKING");
        d.vsExtensions = "#extension GL_OVR_multiview : require\n";
    } else if (method == "kalaiah-emulation") {
        def("VS_KALAIAH");
    }
    const std::string key = d.vsExtensions + defs + (d.geometry ? "GS" : "");
    if (auto it = mPrograms.find(key); it != mPrograms.end()) return it->second.get();
    if (auto it = mProgramErrors.find(key); it != mProgramErrors.end()) return it->second;
    auto p = buildProgram(d);
    if (!p) {
        Status s(p.status().code(), fmt::format("gl: {}: {}", method, p.status().message()));
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
        glBindVertexArray(f.flatProvoking ? g.flatVao.get() : g.vao.get());
        if (instances > 1) {
            glDrawElementsInstanced(GL_TRIANGLES, g.indexCount, GL_UNSIGNED_INT, nullptr,
                                    instances);
        } else {
            glDrawElements(GL_TRIANGLES, g.indexCount, GL_UNSIGNED_INT, nullptr);
        }
    }
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

// Reads a w×h region of one layer, flipping rows (GL row 0 = bottom, image row 0 = top).
void readRegion(GLuint tex, int x, int y, int layer, int w, int h, Image& img) {
    img = Image(w, h);
    std::vector<std::uint8_t> tmp(static_cast<std::size_t>(w) * h * 4);
    glGetTextureSubImage(tex, 0, x, y, layer, w, h, 1, GL_RGBA, GL_UNSIGNED_BYTE,
                         static_cast<GLsizei>(tmp.size()), tmp.data());
    const std::size_t row = static_cast<std::size_t>(w) * 4;
    for (int r = 0; r < h; ++r) {
        std::memcpy(img.row(r), tmp.data() + static_cast<std::size_t>(h - 1 - r) * row, row);
    }
}

void readDepthRegion(GLuint tex, int x, int y, int layer, int w, int h, DepthImage& img) {
    img = DepthImage(w, h);
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
    out.color.resize(static_cast<std::size_t>(f.views));
    if (depth) out.depth.resize(static_cast<std::size_t>(f.views));
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    for (int v = 0; v < f.views; ++v) {
        readRegion(mLayered.color.get(), 0, 0, v, w, h, out.color[static_cast<std::size_t>(v)]);
        if (depth) {
            readDepthRegion(mLayered.depth.get(), 0, 0, v, w, h,
                            out.depth[static_cast<std::size_t>(v)]);
        }
    }
}

void Renderer::readTiled(RenderOutput& out, const Frame& f, const TileLayout& t) {
    out.color.resize(static_cast<std::size_t>(f.views));
    out.depth.resize(static_cast<std::size_t>(f.views));
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    for (int v = 0; v < f.views; ++v) {
        const glm::ivec2 o = t.origin(v);
        readRegion(mTiled.color.get(), o.x, o.y, 0, t.width, t.height,
                   out.color[static_cast<std::size_t>(v)]);
        readDepthRegion(mTiled.depth.get(), o.x, o.y, 0, t.width, t.height,
                        out.depth[static_cast<std::size_t>(v)]);
    }
}

void Renderer::readMrt(RenderOutput& out, const Frame& f) {
    out.color.resize(2);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    for (int v = 0; v < 2; ++v) {
        readRegion(mMrt.color[v].get(), 0, 0, 0, f.settings->width, f.settings->height,
                   out.color[static_cast<std::size_t>(v)]);
    }
}

// ---- render ----------------------------------------------------------------------------------

Result<RenderOutput> Renderer::render(const Scene& scene, const Rig& rig, const RenderSettings& s,
                                      const std::string& method) {
    if (Status st = supports(method); !st) return st;
    if (Status st = validateRequest(scene, rig, s); !st) return st;
    if (method == "auto") return renderAuto(scene, rig, s);
    return renderOnce(scene, rig, s, method);
}

Result<RenderOutput> Renderer::renderOnce(const Scene& scene, const Rig& rig,
                                          const RenderSettings& s, const std::string& method) {
    const auto t0 = Clock::now();
    if (Status st = checkViews(method, rig.viewCount(), s); !st) return st;
    Frame f;
    f.scene = &scene;
    f.rig = &rig;
    f.settings = &s;
    f.views = rig.viewCount();
    if (Status st = prepareScene(scene, f, mLastSceneKey); !st) return st;
    f.order.resize(scene.instances.size());
    for (std::size_t i = 0; i < f.order.size(); ++i) f.order[i] = static_cast<int>(i);

    f.flatProvoking = s.shading == Shading::Flat &&
                      (method == "multipass" || method == "instanced-layer" || method == "multiview");
    Result<GLuint> prog = program(method, f);
    if (!prog) return prog.status();

    std::optional<TileLayout> tiles;
    if (method == "viewport-array" || method == "kalaiah-emulation") {
        auto t = tileLayout(rig, s.width, s.height,
                            method == "viewport-array" ? mCaps.maxViewports : kMaxViews);
        if (!t) return t.status();
        tiles = *t;
    }
    if (method == "kalaiah-emulation") {
        for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
            if (Status st = ensureKalaiahBuffers(*f.meshes[i], scene.meshes[i], f.views); !st)
                return st;
        }
    }
    uploadFrameBlock(f, tiles ? &*tiles : nullptr);
    setCommonState(s);
    glUseProgram(*prog);
    if (Status st = checkGlError("setting up the frame"); !st) return st;

    const auto tDraw = Clock::now();
    if (mTimer) glBeginQuery(GL_TIME_ELAPSED, mTimer.get());
    Status drawn;
    if (method == "multipass") drawn = drawMultipass(f, *prog);
    else if (method == "gs-layered" || method == "gs-invocations") drawn = drawLayeredGs(f, *prog);
    else if (method == "instanced-layer") drawn = drawInstancedLayer(f, *prog);
    else if (method == "multiview") drawn = drawMultiview(f, *prog);
    else if (method == "viewport-array") drawn = drawViewportArray(f, *prog, *tiles);
    else if (method == "kalaiah-emulation") drawn = drawKalaiah(f, *prog, *tiles);
    else if (method == "gs-mrt") drawn = drawGsMrt(f, *prog, false);
    else if (method == "gs-depthmap") drawn = drawGsMrt(f, *prog, true);
    else drawn = internalError("gl: no draw path for " + method);
    if (mTimer) glEndQuery(GL_TIME_ELAPSED);
    glFinish();
    const double drawMs = msSince(tDraw);
    if (!drawn) return drawn;
    if (Status st = checkGlError(fmt::format("drawing with {}", method).c_str()); !st) return st;

    const auto tRead = Clock::now();
    RenderOutput out;
    out.method = method;
    if (method == "gs-mrt") {
        out.note = "sorbier2008 one-pass stereo: depth test off, instances in painter's order "
                   "(back to front); no per-view depth; hidden faces of concave objects may show";
    } else if (method == "gs-depthmap") {
        out.note = "sorbier2008 §5.2: left-eye depth pre-pass, both eyes tested against it; no "
                   "per-view depth; the right eye may lose surfaces the left eye cannot see";
    }
    if (method == "gs-mrt" || method == "gs-depthmap") readMrt(out, f);
    else if (tiles) readTiled(out, f, *tiles);
    else readLayered(out, f, true);
    if (Status st = checkGlError("reading back"); !st) return st;
    const double readMs = msSince(tRead);

    GlFrameStats stats;
    stats.method = method;
    stats.gpuMs = -1.0;
    if (mTimer) {
        GLuint64 ns = 0;
        glGetQueryObjectui64v(mTimer.get(), GL_QUERY_RESULT, &ns);
        stats.gpuMs = static_cast<double>(ns) * 1e-6;
    }
    stats.drawWallMs = drawMs;
    stats.readbackWallMs = readMs;
    stats.totalWallMs = msSince(t0);
    mLastStats = stats;
    return out;
}

Result<RenderOutput> Renderer::renderAuto(const Scene& scene, const Rig& rig,
                                          const RenderSettings& s) {
    // Only methods that give every view its own depth buffer (identical images): gs-mrt and
    // gs-depthmap trade correctness for speed (sorbier2008's painter's order), so auto never
    // picks them.
    Frame probe;
    std::uint64_t sceneKey = 0;
    if (Status st = prepareScene(scene, probe, sceneKey); !st) return st;
    const std::string key = fmt::format("{:x}/{}x{}/{}/{}/{}{}", sceneKey, s.width, s.height,
                                        rig.viewCount(), shadingName(s.shading),
                                        s.cullBackFaces, s.wireframe);
    if (auto it = mAutoChoices.find(key); it != mAutoChoices.end()) {
        auto r = renderOnce(scene, rig, s, it->second.method);
        if (!r) return r;
        r->method = it->second.method;
        r->note = it->second.note;
        return r;
    }
    std::vector<std::pair<double, std::string>> times;
    std::vector<std::string> skipped;
    for (const std::string& m : methodNames()) {
        if (m == "auto" || m == "gs-mrt" || m == "gs-depthmap") continue;
        if (Status st = supports(m); !st) { skipped.push_back(m + " (unsupported)"); continue; }
        if (Status st = checkViews(m, rig.viewCount(), s); !st) {
            skipped.push_back(m + " (view limit)");
            continue;
        }
        // One warm-up (compiles, allocates), then the best of two timed renders.
        double ms = 1e300;
        bool failed = false;
        for (int run = 0; run < 3 && !failed; ++run) {
            auto r = renderOnce(scene, rig, s, m);
            if (!r) { skipped.push_back(m + " (" + r.status().message() + ")"); failed = true; break; }
            if (run > 0) ms = std::min(ms, mLastStats->totalWallMs);
        }
        if (failed) continue;
        times.emplace_back(ms, m);
    }
    if (times.empty()) return unsupportedError("gl: auto: no method can render this here: " +
                                       fmt::format("{}", fmt::join(skipped, ", ")));
    std::sort(times.begin(), times.end());
    std::vector<std::string> parts;
    for (auto& [ms, m] : times) parts.push_back(fmt::format("{} {:.2f} ms", m, ms));
    AutoChoice c;
    c.method = times.front().second;
    c.note = fmt::format("auto picked {}: fastest of the exact (per-view depth) methods measured "
                         "on {} for {} views at {}x{} ({}); gs-mrt/gs-depthmap excluded "
                         "(painter's-order artifacts){}",
                         c.method, mCaps.renderer, rig.viewCount(), s.width, s.height,
                         fmt::join(parts, ", "),
                         skipped.empty() ? "" : fmt::format("; skipped: {}", fmt::join(skipped, ", ")));
    mAutoChoices[key] = c;
    auto r = renderOnce(scene, rig, s, c.method);  // the returned images and stats are its
    if (!r) return r;
    r->method = c.method;
    r->note = c.note;
    return r;
}

}  // namespace mvr::gl::detail

// src/gl/renderer.h — the gl backend's internals: context, GPU copies of meshes, render
// targets, programs and the per-method draw paths (methods.cpp).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include <glm/glm.hpp>

#include "caps.h"
#include "egl_context.h"
#include "gl_objects.h"
#include "method_table.h"
#include "mvr/core/environment.h"
#include "mvr/core/render.h"
#include "mvr/core/rig.h"
#include "mvr/core/scene.h"
#include "mvr/core/shadows.h"
#include "mvr/gl/gl_backend.h"
#include "shaders.h"

namespace mvr::gl::detail {

/// One mesh on the GPU. Keyed by a hash of its contents, so a scene object that is rendered
/// again (bench loops) is not uploaded again, and a changed mesh is.
struct GpuMesh {
    Buffer positions, normals, indices;
    Buffer texcoords;  ///< one per position (zeros when the mesh has none)
    Buffer colors;     ///< one linear RGBA per position (white when the mesh has none)
    /// Mesh::tangents (attribute 5); none when the mesh has none: the attribute is disabled and
    /// reads its constant (0, 0, 0, 1), a degenerate frame that keeps the normal.
    Buffer tangents;
    VertexArray vao;
    GLsizei indexCount = 0;
    // Flat shading without a geometry shader, as glShadeModel(GL_FLAT) did it: every
    // triangle's last (provoking) vertex is its own, carrying the model-space face normal
    // (edge cross product); the vertex shader shades it and the colour is `flat`.
    Buffer flatPositions, flatNormals, flatIndices;
    Buffer flatTexcoords, flatCenters;  ///< per flat vertex; the centre: its face's centroid
    Buffer flatColors;                  ///< per flat vertex
    VertexArray flatVao;
    GLsizei triangleCount = 0;
    Bounds bounds;
    // kalaiah2007 emulation: per-triangle corners + normals (divisor 1) and the dummy array.
    Buffer kalaiahTriangles;
    Buffer kalaiahTexcoords;  ///< per triangle: t0 t1 t2
    Buffer kalaiahColors;     ///< per triangle: c0 c1 c2 (attributes 10–12)
    Buffer kalaiahTangents;   ///< per triangle: the corners' tangents (attributes 13–15), if any
    VertexArray kalaiahVao;
    int kalaiahViews = 0;
    Buffer kalaiahDummy;
    std::uint64_t lastUse = 0;
};

/// GPU copies kept between renders beyond what the current one uses.
inline constexpr std::size_t kMeshesKept = 32;
inline constexpr std::size_t kTexturesKept = 64;
/// The most views one target holds (layers of an array, tiles of a partitioned target): a
/// read-back of one view from a larger target costs more than the view itself on Mesa (it
/// maps the whole target), so many views are drawn in passes of at most this many, each
/// read back while the next is drawn. Larger passes repeat less vertex work; 32 layers read
/// back linearly on llvmpipe, zink and NVIDIA, tiles of one 2D target 16 (src/gl/README.md,
/// "Read-back").
inline constexpr int kLayersPerTarget = 32;
inline constexpr int kTilesPerTarget = 16;

/// Drops least recently used entries of `cache` (values with a `lastUse`) while it holds
/// `keep` or more, but never one used by the current render (lastUse == `now`): that one is
/// still referenced by the frame being prepared.
template <class Map>
void evictLeastRecentlyUsed(Map& cache, std::size_t keep, std::uint64_t now) {
    while (cache.size() >= keep) {
        auto lru = cache.end();
        for (auto it = cache.begin(); it != cache.end(); ++it) {
            if (it->second.lastUse < now &&
                (lru == cache.end() || it->second.lastUse < lru->second.lastUse))
                lru = it;
        }
        if (lru == cache.end()) return;  // all in use by this render: keep them
        cache.erase(lru);
    }
}

/// The std140 "Frame" uniform block of shaders.cpp (its MAX_VIEWS / MAX_LIGHTS are these).
struct FrameBlock {
    glm::mat4 clipFromWorld[kMaxViews];
    glm::vec4 tile[kMaxViews];
    glm::vec4 lightDir[kMaxLights];
    glm::vec4 lightColor[kMaxLights];
    glm::vec4 ambient;
    glm::vec4 centerEye;
    glm::ivec4 counts;
    // Appended (point / spot lights): xyz position, w type (0 directional, 1 point, 2 spot);
    // x range, y cos inner cone, z cos outer cone.
    glm::vec4 lightPos[kMaxLights];
    glm::vec4 lightCone[kMaxLights];
    // Appended (--specular per-view): each view's eye, world space.
    glm::vec4 viewEye[kMaxViews];
    // Appended (image lighting, ENVIRONMENT programs): Environment::sh, rgb (zeros: none).
    glm::vec4 envSh[9];
};
// std140: mat4 arrays have a 64-byte stride, vec4 / ivec4 arrays and members 16 bytes, no padding.
static_assert(std::extent_v<decltype(FrameBlock::clipFromWorld)> == kMaxViews);
static_assert(std::extent_v<decltype(FrameBlock::tile)> == kMaxViews);
static_assert(std::extent_v<decltype(FrameBlock::lightDir)> == kMaxLights);
static_assert(std::extent_v<decltype(FrameBlock::lightColor)> == kMaxLights);
static_assert(sizeof(glm::mat4) == 64 && sizeof(glm::vec4) == 16 && sizeof(glm::ivec4) == 16);
static_assert(offsetof(FrameBlock, tile) == 64 * kMaxViews);
static_assert(offsetof(FrameBlock, lightDir) == 80 * kMaxViews);
static_assert(offsetof(FrameBlock, lightColor) == 80 * kMaxViews + 16 * kMaxLights);
static_assert(offsetof(FrameBlock, ambient) == 80 * kMaxViews + 32 * kMaxLights);
static_assert(offsetof(FrameBlock, centerEye) == 80 * kMaxViews + 32 * kMaxLights + 16);
static_assert(offsetof(FrameBlock, counts) == 80 * kMaxViews + 32 * kMaxLights + 32);
static_assert(offsetof(FrameBlock, viewEye) == 80 * kMaxViews + 64 * kMaxLights + 48);
static_assert(sizeof(FrameBlock) <= 16384);  // GL's smallest GL_MAX_UNIFORM_BLOCK_SIZE
static_assert(offsetof(FrameBlock, lightPos) == 80 * kMaxViews + 32 * kMaxLights + 48);
static_assert(offsetof(FrameBlock, envSh) == 96 * kMaxViews + 64 * kMaxLights + 48);
static_assert(sizeof(FrameBlock) == 96 * kMaxViews + 64 * kMaxLights + 48 + 9 * 16);

/// Image lighting's texture units (shaders.cpp ENVIRONMENT): the prefiltered levels (one
/// RGBA32F texture, mip levels 0..Environment::kLevels − 1) and the split sum's table (RG32F).
/// Units 0–1 are the methods' and read-back's, 2 and 4–7 the material's slots, 3 the shadow
/// maps.
inline constexpr GLuint kEnvironmentUnit = 8;
inline constexpr GLuint kSplitSumUnit = 9;

/// One scene texture on the GPU (GL_SRGB8_ALPHA8, or GL_RGBA8 for a linear one, with its full
/// mip chain), keyed by a hash of its pixels and whether it is linear, so a scene rendered
/// again uploads nothing.
struct GpuTexture {
    Texture texture;
    std::uint64_t lastUse = 0;
};

/// Where each view lies in a tiled (partitioned / side-by-side) target.
struct TileLayout {
    int columns = 1, rows = 1;
    int width = 0, height = 0;  ///< of one view
    /// Pixel origin of view `view`'s tile in the target, whose rows run top-down (the
    /// renderer draws with an upper-left clip origin); view 0 is the top-left tile.
    glm::ivec2 origin(int view) const {
        return {(view % columns) * width, (view / columns) * height};
    }
};

/// Per-call inputs shared by the draw paths.
struct Frame {
    const GlMethod* method = nullptr;
    const Scene* scene = nullptr;
    const Rig* rig = nullptr;
    const RenderSettings* settings = nullptr;
    int views = 0;                    ///< of this pass (rig->views are this pass's views)
    int firstView = 0;                ///< the request's index of this pass's view 0
    int targetViews = 0;              ///< views the target holds: the largest pass's
    int samples = 1;                  ///< the targets' samples a pixel (> 1: multisampled)
    std::vector<GpuMesh*> meshes;     ///< per scene mesh
    std::vector<int> order;           ///< instance draw order (AlphaMode::Blend ones last)
    std::vector<GLuint> textures;     ///< per scene texture: its GL texture
    bool flatProvoking = false;       ///< draw the provoking-vertex flat arrays
    std::optional<TileLayout> tiles;  ///< where the views lie in a TargetKind::Tiled target
};

/// The order instances are drawn in (lighting.h): opaque and masked ones in scene order, then
/// the AlphaMode::Blend ones, in scene order too (unsorted, as the soft backend draws them).
std::vector<int> drawOrder(const Scene& scene);

/// The render targets: one colour + depth pair per target kind, reallocated when the size
/// changes. Multiview attachments get a framebuffer of their own (never shared with the
/// layered / per-layer attachments of the other methods).
///
/// `--aa N` where the driver multisamples N (GlCaps::sampleCounts, GlMethod::multisample): the
/// methods draw into multisampled twins of the colour and depth (ms*, `samples` a pixel), and
/// Renderer::resolveSamples() resolves them into the single-sample textures through
/// `resolveFbo` (antialias.h's resolve: the mean colour rounded half up, the nearest depth),
/// which the read-back reads as at one sample.
struct LayeredTarget {
    int w = 0, h = 0, layers = 0, samples = 1;
    Texture color, depth;
    Texture msColor, msDepth;  ///< samples > 1: what the methods draw into
    Framebuffer fbo, multiviewFbo, resolveFbo;
    GLuint drawColor() const { return samples > 1 ? msColor.get() : color.get(); }
    GLuint drawDepth() const { return samples > 1 ? msDepth.get() : depth.get(); }
};
struct MrtTarget {
    int w = 0, h = 0, samples = 1;
    Texture color[2], depthMap;
    Texture msColor[2];  ///< samples > 1: fbo's attachments (the depth map stays one sample)
    Framebuffer fbo, depthFbo, resolveFbo;
};
struct TiledTarget {
    int w = 0, h = 0, samples = 1;
    Texture color, depth;
    Texture msColor, msDepth;  ///< samples > 1: fbo's attachments
    Framebuffer fbo, resolveFbo;
};

/// A pixel-pack buffer the views' pixels are read into (mapped once they have arrived).
struct ReadBuffer {
    Buffer buffer;
    std::size_t bytes = 0;
};

/// One pass's pixels on their way back: the reads went into `buffer` (an index into
/// GpuObjects::reads), `fence` follows them. Colour of view k at k·w·h·4, depth after all
/// colour (when asked).
struct PendingRead {
    int firstView = 0, views = 0, width = 0, height = 0;
    bool depth = false;
    int buffer = 0;
    GLsync fence = nullptr;
};

/// Every GL object of a Renderer (see Renderer::mGpu).
struct GpuObjects {
    ReadBuffer reads[2];  ///< ping-pong: pass p reads into p % 2 while p − 1's is mapped
    std::map<std::uint64_t, GpuMesh> meshes;
    std::map<std::uint64_t, GpuTexture> textures;
    std::map<int, Sampler> samplers;
    std::map<std::string, Program> programs;
    Buffer frameUbo;
    std::vector<Query> timers;  ///< GL_TIME_ELAPSED, one a pass
    VertexArray emptyVao;
    LayeredTarget layered;
    MrtTarget mrt;
    TiledTarget tiled;
    Texture shadowMaps;
    /// Image lighting (Scene::environment): the prefiltered levels of `environmentSource`,
    /// uploaded once per Environment object (re-uploaded when the scene holds another one, or
    /// the same address rebuilt: the weak pointer expired, or other SH coefficients), and the
    /// split sum's table, uploaded once.
    Texture environment;
    std::weak_ptr<const Environment> environmentSource;
    std::array<glm::vec3, 9> environmentSh{};
    Texture splitSum;
    Program depthRangeProgram;  ///< readback.cpp: the views' depth ranges (built on first use)
    /// resolveSamples()'s programs, by target kind and sample count (built on first use).
    std::map<std::pair<int, int>, Program> resolvePrograms;
    Buffer depthRanges;         ///< 2 uints a view: the nearest and farthest depth's bits
};

class Renderer {
public:
    Renderer() = default;
    ~Renderer();

    /// Creates the EGL context on first use; the same Status thereafter.
    Status ensureContext();
    const GlCaps& caps() const { return mCaps; }
    std::vector<std::string> info();

    /// Can this driver run `method` at all? (Usage for an unknown name.)
    Status supports(const std::string& method);
    /// Does `method` draw `samples` samples a pixel into multisampled targets here (the row's
    /// GlMethod::multisample and the driver's GlCaps::sampleCounts; "auto": the driver's)?
    /// Else the backend's `--aa N` renders sub-pixel passes (antialias.h renderSampled).
    /// MVR_GL_MULTISAMPLE=off says no to every request (the passes, for comparisons).
    bool multisamples(const std::string& method, int samples);
    /// Does the row `method` draw `samples` a pixel into multisampled targets on this driver
    /// (GlMethod::multisample and GlCaps::sampleCounts)?
    bool drawsSamples(const GlMethod& method, int samples) const;
    /// The largest view count `method` allows here for this shading and view size (0: none);
    /// in pixel shading with normal maps (mNormalMaps), their geometry shaders' limits.
    int viewLimit(const GlMethod& method, Shading shading, int width, int height) const;
    /// The views one pass of `method` draws here: its table limit (viewLimit), the bounded
    /// target (kLayersPerTarget / kTilesPerTarget: a read costs what it reads) and the count
    /// the driver links the method's program at (probed on first use by building smaller
    /// programs when the table's count is refused; remembered per method, shading and
    /// shadows). 0 when not even one view links (`why` says why).
    int passLimit(const GlMethod& method, Shading shading, int width, int height, bool shadows,
                  Status* why = nullptr);
    /// At most `limit`: the views a pass of `method` draws with a program this driver links
    /// (see passLimit). 0 when not even one view links (`why` says why).
    int linkedViewLimit(const GlMethod& method, Shading shading, bool shadows, int limit,
                        Status* why = nullptr);
    /// Checks `views` against the target budget and the method's limits, naming the limit
    /// that is exceeded.
    Status checkViews(const GlMethod& method, int views, const RenderSettings& s) const;

    /// Renders into `out`, reusing its images where they have the request's size.
    Status renderInto(const Scene& scene, const Rig& rig, const RenderSettings& s,
                      const std::string& method, RenderOutput& out);

    const std::optional<GlFrameStats>& lastStats() const { return mLastStats; }

    /// Shadows (issue 15): the maps the next renders sample (null or empty: none), uploaded
    /// once into an R32F texture array (one layer per map). The caller keeps `set` alive.
    void setShadows(const ShadowSet* set, const std::vector<Light>& lights = {});
    /// The method the shadow pass of a render with `method` uses: `method` itself when it
    /// returns per-view depth (an exact row), else the reference row (multipass).
    std::string shadowPassMethod(const std::string& method) const;

private:
    // The table's rows name the draw paths below.
    friend const std::vector<GlMethod>& glMethods();

    Status supportsMethod(const GlMethod& method);
    /// Draws the views in passes of at most the method's per-pass limit (kalaiah2007 §3),
    /// each pass into the same target, read back into its views' places.
    Status renderOnce(const Scene& scene, const Rig& rig, const RenderSettings& s,
                      const GlMethod& method, RenderOutput& out);
    /// One pass of renderOnce: draws f's views, adds its times to `stats` (startRead reads them).
    Status drawPass(Frame& f, int pass, GlFrameStats& stats);
    Status renderAuto(const Scene& scene, const Rig& rig, const RenderSettings& s,
                      RenderOutput& out);

    Status prepareScene(const Scene& scene, Frame& frame, std::uint64_t& sceneKey);
    /// Image lighting: scene.environment's textures on the GPU (once per Environment, the split
    /// sum's table once per renderer); nothing without one.
    Status prepareEnvironment(const Scene& scene);
    /// Binds them on kEnvironmentUnit / kSplitSumUnit (a pass of an ENVIRONMENT program).
    void bindEnvironment() const;
    /// Uploads the scene's textures not on the GPU yet (materials.cpp); frame.textures.
    Status prepareTextures(const Scene& scene, Frame& frame, std::uint64_t& sceneKey);
    void uploadFrameBlock(const Frame& frame);
    /// The program of `desc`, built once; build errors say "gl: LABEL: …".
    Result<GLuint> program(const std::string& label, const ProgramDesc& desc);
    /// The program one pass of `views` views of `method` draws with.
    /// perViewEye: each fragment shaded from its view's eye (shadesFromEachEye).
    ProgramDesc passProgram(const GlMethod& method, Shading shading, int views, bool shadows,
                            bool perViewEye = false) const;
    void setInstanceUniforms(GLuint program, const Instance& instance);
    /// The instance's material state: its textures bound with its sampler (base colour unit 2,
    /// metallic-roughness 4, occlusion 5, emissive 6, normal 7: materials.cpp kSlotUnits),
    /// culling off when double-sided, blending with depth writes off for AlphaMode::Blend.
    void setInstanceState(const Frame& f, const Instance& instance);
    /// Back to the frame's state after the instances (depth writes on, no blending, culling
    /// as the settings say).
    void endInstanceState(const Frame& f);
    /// The GL sampler object for `s`, made once.
    GLuint sampler(const TextureSampler& s);
    void setCommonState(const RenderSettings& s);
    Status ensureKalaiahBuffers(GpuMesh& mesh, const Mesh& source, int views);
    Result<TileLayout> tileLayout(const Rig& rig, int width, int height) const;

    // Per-frame preparations and draw paths (methods.cpp), named by the method table; each
    // draw leaves its results in the targets below.
    Status prepareKalaiah(const Frame& f);
    Status drawMultipass(const Frame& f, GLuint program);
    Status drawLayeredGs(const Frame& f, GLuint program);
    Status drawInstancedLayer(const Frame& f, GLuint program);
    Status drawMultiview(const Frame& f, GLuint program);
    Status drawViewportArray(const Frame& f, GLuint program);
    Status drawKalaiah(const Frame& f, GLuint program);
    Status drawGsMrt(const Frame& f, GLuint program);
    Status drawGsDepthMap(const Frame& f, GLuint program);
    Status drawSorbier(const Frame& f, GLuint program, bool depthMap);
    void drawScene(const Frame& f, GLuint program, int instances);

    // Targets, reallocated when their size or sample count changes.
    void ensureLayered(int w, int h, int layers, int samples);
    void ensureMrt(int w, int h, int samples);
    void ensureTiled(int w, int h, int samples);
    /// f.samples > 1: the multisampled target of f's pass resolved into its single-sample
    /// textures (LayeredTarget), view by view: colour = (Σ samples' bytes + N/2) / N, depth =
    /// the nearest sample. Leaves the state setCommonState() sets again.
    Status resolveSamples(const Frame& f);
    /// Reads pass f's views back. Software rasterisers: straight into out's images (rows in
    /// image order: the targets are drawn with an upper-left origin, no flip). Else: into a
    /// pixel-pack buffer with a fence, returned pending; finishRead() maps it after the next
    /// pass is drawn, so the transfer overlaps that draw.
    std::optional<PendingRead> startRead(const Frame& f, RenderOutput& out, int pass);
    void finishRead(PendingRead& r, RenderOutput& out, const RenderSettings& s);
    /// Each view's regions of f's target: texture, x, y (upper-left origin), layer.
    struct ViewRegion {
        GLuint color = 0, depth = 0;
        int x = 0, y = 0, layer = 0;
    };
    std::vector<ViewRegion> viewRegions(const Frame& f) const;
    /// RenderSettings::depth false: each view's DepthRange without reading its depth image
    /// back. begin (before the first pass) resets the ranges of `views` views; reduce (after
    /// each pass's draw) folds pass f's depth into them on the GPU (a compute shader, atomic
    /// min / max of the float bits: non-negative floats order as their bits); read (after the
    /// last pass) returns 8 bytes a view into out.depthRange.
    /// Whether the ranges are reduced on the GPU: on hardware drivers. llvmpipe runs the
    /// compute reduction ~5x slower than it reads the depth back (45 views, 420x560: 57 ms vs
    /// 12), so software drivers read each view's depth into scratch memory and reduce it on the
    /// CPU (4 lanes a step); MVR_GL_DEPTH_RANGES=gpu forces the GPU (the tests).
    bool gpuDepthRanges() const;
    Status beginDepthRanges(int views);
    Status reduceDepthRanges(const Frame& f);
    Status readDepthRanges(RenderOutput& out, int views);
    /// Software drivers: region r's depth read into mDepthScratch, its range.
    DepthRange scratchDepthRange(const ViewRegion& r, int w, int h);

    // Declared first, so destroyed last: no GL object outlives its context.
    std::unique_ptr<EglContext> mContext;
    std::optional<Status> mContextStatus;
    GlCaps mCaps;
    /// Every GL object the renderer owns, made with the context and destroyed (in ~Renderer)
    /// while it is current; one owner per object, no hand-kept list of names.
    std::unique_ptr<GpuObjects> mGpu;
    std::uint64_t mUseCounter = 0;
    std::map<std::string, Status> mProgramErrors;
    /// Views per pass that programs with a geometry-shader loop link at, found on this driver
    /// (a driver may refuse below GL_MAX_GEOMETRY_OUTPUT_VERTICES / _TOTAL_OUTPUT_COMPONENTS:
    /// NVIDIA's "can only emit 78 vertices of this size"); key: method / shading.
    std::map<std::string, int> mLinkedViewLimit;
    std::vector<float> mDepthScratch;  ///< software drivers' depth of one view, for its range
    /// The geometry-shader program of the last pass (0: it had none); see drawPass.
    GLuint mLastGeometryProgram = 0;

    struct AutoChoice {
        const GlMethod* method = nullptr;
        std::string note;
    };
    std::map<std::string, AutoChoice> mAutoChoices;
    std::optional<GlFrameStats> mLastStats;
    std::uint64_t mLastSceneKey = 0;
    const ShadowSet* mShadows = nullptr;
    /// Some mesh of the frame being drawn has vertex colours: its programs are built with
    /// VERTEX_COLORS (shaders.cpp), as the soft backend's FrameContext::colored.
    bool mVertexColors = false;
    /// The frame being drawn is shaded per pixel and some instance has a normal map on a mesh
    /// with tangents (the soft backend's FrameContext::tangents): its programs are built with
    /// NORMAL_MAPS (the world tangent as a varying, the normal map on unit 7), and its geometry
    /// shaders' view limits count the tangent's 4 components. Other frames' programs, varyings
    /// and limits are those of a build without normal maps.
    bool mNormalMaps = false;
    /// Whether `scene` drawn with `s` is such a frame.
    static bool drawsNormalMaps(const Scene& scene, const RenderSettings& s);
    /// The frame being drawn has an environment (Scene::environment): its programs are built
    /// with ENVIRONMENT (shaders.cpp: the SH in the Frame block, the prefiltered map and the
    /// split sum's table on units 8 and 9); no varying is added, so the view limits are those
    /// of a frame without. Other frames' programs are unchanged.
    bool mEnvironment = false;
    std::vector<Light> mShadowLights;
    void setShadowUniforms(GLuint program) const;
};

}  // namespace mvr::gl::detail

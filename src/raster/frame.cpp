#include "frame.h"

#include "cpu.h"

#if defined(__x86_64__)
#include <immintrin.h>
#elif defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>

#include <glm/gtc/matrix_transform.hpp>

namespace mvr::raster::detail {

DrawList makeDrawList(const Scene& scene) {
    DrawList list;
    // Opaque and masked instances first, blended ones after them (each group in instance order).
    std::vector<const Instance*> order;
    for (const Instance& inst : scene.instances)
        if (inst.material.alphaMode != AlphaMode::Blend) order.push_back(&inst);
    for (const Instance& inst : scene.instances)
        if (inst.material.alphaMode == AlphaMode::Blend) order.push_back(&inst);
    for (const Instance* instp : order) {
        const Instance& inst = *instp;
        const Mesh& mesh = scene.meshes[static_cast<std::size_t>(inst.mesh)];
        DrawItem item{&mesh, &inst, list.vertexCount, list.triangleCount,
                      glm::transpose(glm::inverse(glm::mat3(inst.worldFromModel)))};
        list.items.push_back(item);
        list.vertexCount += static_cast<std::uint32_t>(mesh.positions.size());
        list.triangleCount += static_cast<std::uint32_t>(mesh.triangleCount());
    }
    return list;
}

glm::mat4 centerClipFromWorld(const Rig& rig) {
    if (rig.clipJitter != glm::vec2(0.0f)) {  // a sub-pixel sample (antialias.h)
        const glm::mat4 move = glm::translate(glm::mat4(1.0f), glm::vec3(rig.clipJitter, 0.0f));
        return move * rig.camera.clipFromView() * rig.camera.viewFromWorld();
    }
    return rig.camera.clipFromView() * rig.camera.viewFromWorld();
}

BandLayout makeBands(int height, int threads, std::size_t bytesPerRow) {
    // About eight bands per worker, at least 16 rows each (a triangle straddling a band boundary
    // is set up once per band it touches): load balance, and a band's depth and color rows stay
    // in the core's L2 (1024×768, 2 workers: 48 rows × 8 bytes per pixel ≈ 0.4 MB per view;
    // measured: 4 per worker → 8 per worker takes ~2–3 ms off a 9-bunny stereo frame).
    BandLayout b;
    b.height = height;
    const int want = std::max(1, threads * 8);
    b.rows = std::max(16, (height + want - 1) / want);
    if (bytesPerRow > 0) {
        // Many views (issue 12): a band spans every view, so its rows of all views must fit the
        // core's L2 as well (~768 KiB of the 1 MiB; a stereo pair of 1024 px: 48 rows, as above),
        // down to 4 rows (45 views of 420 px: 5 rows, 100 views: 4). Fewer rows per band cost a
        // little binning and the setup of triangles that straddle bands; the depth tests then
        // hit L2 instead of L3/DRAM (100 views, 420x560: CPU per frame -15 %).
        constexpr std::size_t kBandBytes = 768u << 10;
        constexpr int kMinBandRows = 4;
        b.rows = std::min(b.rows, std::max(kMinBandRows, int(kBandBytes / bytesPerRow)));
    }
    b.count = (height + b.rows - 1) / b.rows;
    b.rowsReciprocal =
        ((std::uint64_t(1) << 40) + std::uint64_t(b.rows) - 1) / std::uint64_t(b.rows);
    return b;
}

void Bins::reset(std::uint32_t triangleCount, int bands) {
    chunkCount = static_cast<int>(std::clamp<std::uint32_t>(triangleCount / 8192u, 1u, 64u));
    chunkSize = (triangleCount + chunkCount - 1) / chunkCount;
    if (chunkSize == 0) chunkSize = 1;
    lists.resize(std::size_t(chunkCount) * bands);
    for (auto& l : lists) l.clear();
}

namespace {

/// n values (4 bytes each) from src to dst, the part of dst aligned to whole registers with
/// streaming stores (non-temporal: the lines go to memory without being read first or kept in
/// the cache). With AVX-512 a store writes a whole line (against 16-byte stores, Sapphire
/// Rapids, 420x560, 3 rounds: 45 views 47.2 -> 46.5 ms, 100 views 81.2 -> 78.7 ms; 32-byte AVX2
/// stores were no faster than 16-byte ones there, 48.8 / 82.8 ms).
using StreamCopyFn = void (*)(const std::uint32_t* src, std::uint32_t* dst, std::size_t n);

void streamCopy16(const std::uint32_t* src, std::uint32_t* dst, std::size_t n) {
    std::size_t i = 0;
#if defined(__SSE2__)
    for (; i < n && (reinterpret_cast<std::uintptr_t>(dst + i) & 15u) != 0; ++i) dst[i] = src[i];
    for (; i + 4 <= n; i += 4) {
        _mm_stream_si128(reinterpret_cast<__m128i*>(dst + i),
                         _mm_loadu_si128(reinterpret_cast<const __m128i*>(src + i)));
    }
#endif
    for (; i < n; ++i) dst[i] = src[i];
}

#if defined(__x86_64__)
__attribute__((target("avx512f"))) void streamCopy64(const std::uint32_t* src, std::uint32_t* dst,
                                                     std::size_t n) {
    std::size_t i = 0;
    for (; i < n && (reinterpret_cast<std::uintptr_t>(dst + i) & 63u) != 0; ++i) dst[i] = src[i];
    for (; i + 16 <= n; i += 16)
        _mm512_stream_si512(reinterpret_cast<__m512i*>(dst + i), _mm512_loadu_si512(src + i));
    for (; i < n; ++i) dst[i] = src[i];
}
#endif

/// The widest copy the CPU takes, by the kernels' own detection (cpu.h).
StreamCopyFn pickStreamCopy() {
#if defined(__x86_64__)
    if (bestSupportedSimd() == SimdPath::Avx512) return &streamCopy64;
#endif
    return &streamCopy16;
}

}  // namespace

void streamRows(std::span<const Target> from, std::span<const Target> to, int rowLo, int rowHi) {
    static const StreamCopyFn streamCopy = pickStreamCopy();  // first streamed band, not start-up
    for (std::size_t v = 0; v < to.size(); ++v) {
        const Target& a = from[v];
        const Target& b = to[v];
        const std::size_t count = std::size_t(rowHi - rowLo + 1) * std::size_t(b.width);
        streamCopy(a.color + a.index(0, rowHi), b.color + b.index(0, rowHi), count);
        streamCopy(reinterpret_cast<const std::uint32_t*>(a.depth + a.index(0, rowHi)),
                   reinterpret_cast<std::uint32_t*>(b.depth + b.index(0, rowHi)), count);
    }
    // One fence for the band: a fence waits until every streamed line has left the core's
    // write-combining buffers (a fence per view, as before: 100 views 67.2 -> 63.8 ms, 45 views
    // 40.8 -> 39.7 ms with one per band, Sapphire Rapids, 3 rounds).
#if defined(__SSE2__)
    _mm_sfence();
#endif
}

void allocateOutputs(ThreadPool& pool, RenderOutput& out, int views, const RenderSettings& s,
                     std::vector<Target>& targets) {
    out.color.resize(views);
    out.depth.resize(views);
    targets.resize(views);
    const std::size_t n = std::size_t(s.width) * s.height;
    // One task per view: new buffers are allocated side by side (a new vector is zero-filled).
    // Images of the caller's RenderOutput (Backend::renderInto) that already have the size and
    // live on the heap keep their storage: reallocating them every frame costs a zero fill and,
    // across the workers' malloc arenas, fresh pages (page faults). Nothing is cleared here
    // (clearRows, per band).
    std::pmr::memory_resource* heap = std::pmr::get_default_resource();
    pool.run(views, [&](int v, int) {
        // Into the caller's block when it gave one (RenderSettings::output), else the heap.
        const bool block = s.output && s.output->views() == views && s.output->width() == s.width &&
                           s.output->height() == s.height;
        Image& c = out.color[std::size_t(v)];
        const bool keepColor = !block && c.width == s.width && c.height == s.height &&
                               c.rgba.size() == n * 4 && c.rgba.get_allocator().resource() == heap;
        if (!keepColor) c.reset(s.width, s.height, block ? s.output->colorMemory(v) : nullptr);
        DepthImage& d = out.depth[std::size_t(v)];
        const bool keepDepth = !block && d.width == s.width && d.height == s.height &&
                               d.depth.size() == n && d.depth.get_allocator().resource() == heap;
        if (!keepDepth)
            d.reset(s.width, s.height, 1.0f, block ? s.output->depthMemory(v) : nullptr);
        targets[std::size_t(v)] = Target{reinterpret_cast<std::uint32_t*>(c.rgba.data()),
                                         d.depth.data(), s.width, s.height};
    });
}

}  // namespace mvr::raster::detail

namespace mvr::raster::detail {

void prepareTextures(FrameContext& f) {
    f.textured = false;
    f.colored = false;
    for (const Instance& inst : f.scene.instances) {
        const Material& m = inst.material;
        f.textured = f.textured || hasTexture(m) || m.alphaMode != AlphaMode::Opaque;
        f.colored = f.colored || (inst.mesh >= 0 && std::size_t(inst.mesh) < f.scene.meshes.size() &&
                                  !f.scene.meshes[std::size_t(inst.mesh)].colors.empty());
    }
    f.textured = f.textured || f.colored;
    f.tangents = false;
    if (f.settings.shading == Shading::Pixel) {
        for (const Instance& inst : f.scene.instances) {
            f.tangents = f.tangents ||
                         (inst.material.normalTexture >= 0 && inst.mesh >= 0 &&
                          std::size_t(inst.mesh) < f.scene.meshes.size() &&
                          !f.scene.meshes[std::size_t(inst.mesh)].tangents.empty());
        }
    }
    f.punctualLights = false;
    for (const Light& l : f.scene.lights)
        f.punctualLights = f.punctualLights || l.type != LightType::Directional;
    f.mips.assign(f.textured ? f.scene.textures.size() : 0, MipChain{});
    if (f.mips.empty()) return;
    f.pool.run(int(f.mips.size()), [&](int t, int) {
        const Texture& tex = f.scene.textures[std::size_t(t)];
        // Mip levels are built when any material sampling this texture (in any slot) wants them.
        bool mipmaps = false;
        for (const Instance& inst : f.scene.instances) {
            const Material& m = inst.material;
            const bool samples = m.baseColorTexture == t || m.metallicRoughnessTexture == t ||
                                 m.occlusionTexture == t || m.emissiveTexture == t ||
                                 m.normalTexture == t;
            mipmaps = mipmaps || (samples && m.sampler.mipmaps);
        }
        f.mips[std::size_t(t)] = buildMipChain(tex.image, mipmaps, tex.linear);
    });
}

}  // namespace mvr::raster::detail

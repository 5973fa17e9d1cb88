// mvr/core/texture_sampling.h — the one definition of base color texture sampling that every
// backend implements (the soft backend calls these functions; the gl backend mirrors them in
// GLSL / GL sampler state), after the OpenGL 4.6 core specification §8.14 "Texture
// Minification" and §8.15 "Texture Magnification" with the scale factor c = 0 (§8.14: c = 0.5
// only for mag LINEAR with min *_MIPMAP_NEAREST; see samplerMagnifies).
//
// 1. Decode: texels are sRGB-encoded RGBA8 (scene.h's Texture, straight alpha). Color channels
//    are decoded to linear with the exact IEC 61966-2-1 curve (srgbToLinear: a 256-entry table
//    computed in double, rounded to float once); alpha is linear already (a / 255).
// 2. Mip chain (buildMipChain), built ONCE per texture and render, never per view: level 0 is
//    the decoded image (decoded as it is read: MipLevel::bytes); level k + 1 is max(1, floor(w/2)) × max(1, floor(h/2)) (GL's level
//    sizes), each texel the box average of the 2×2 texels (2i, 2j) .. (2i + 1, 2j + 1) of level
//    k (indices clamped to level k, so a 1-wide level repeats its column; an odd size drops its
//    last row / column, as a 2×2 box must). Filtered in LINEAR space, after the decode: that
//    averages light (a black/white checker becomes 0.5, not sRGB 0.5 = linear 0.21), which is
//    what GL does for sRGB textures (§8.24: the decode happens before filtering), and alpha is
//    averaged straight (not premultiplied), as glGenerateMipmap does.
// 3. Wrap modes on texel indices (§8.14.2, Table 8.20): Repeat i mod n, ClampToEdge
//    clamp(i, 0, n − 1), MirroredRepeat (n − 1) − mirror((i mod 2n) − n), mirror(a) = a ≥ 0 ? a
//    : −(1 + a).
// 4. Filters (texture coordinate (0, 0) is the top-left of image row 0, as glTF; u′ = u·w,
//    v′ = v·h): Nearest texel (wrap(floor(u′)), wrap(floor(v′))); Linear: i0 = floor(u′ − ½),
//    α = frac(u′ − ½), the four texels i0, i0 + 1 (each wrapped) weighted (1 − α)(1 − β), α(1 − β),
//    (1 − α)β, αβ (§8.14.2 eq. 8.11).
// 5. Level of detail (textureLod): ρ = max(‖(∂u/∂x·w, ∂v/∂x·h)‖, ‖(∂u/∂y·w, ∂v/∂y·h)‖) with w, h
//    the size of level 0 and x, y window pixels (§8.14.1 eq. 8.7, the "max of the two lengths"
//    form, not the approximation), λ = log2 ρ (computed as ½·log2 ρ² in float). λ is a per-VIEW
//    quantity: the same surface point is minified differently in each view. The derivatives are
//    of the perspective-correct texture coordinates (uvDerivatives).
// 6. Selection (sampleTexture): λ ≤ 0 (or no mip chain in use and λ ≤ 0): magnification,
//    magFilter on level 0. λ > 0: minification with minFilter: without mipmaps on level 0;
//    with mipmaps and minFilter Linear: LINEAR_MIPMAP_LINEAR (trilinear: d = floor λ, levels d
//    and d + 1 clamped to the last level q, mixed by frac λ; λ ≥ q: level q); with mipmaps and
//    minFilter Nearest: NEAREST_MIPMAP_NEAREST (level d = ceil(λ + ½) − 1 for λ > ½, else 0,
//    clamped to q; nearest texel).
// Result: linear RGBA in [0, 1] (straight alpha). All arithmetic in float in the order written
// below, so that every caller in one binary gets the same bits.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "mvr/core/image.h"
#include "mvr/core/scene.h"

namespace mvr {

/// The 256 linear values of the sRGB-encoded bytes: c = b / 255, c ≤ 0.04045 ? c / 12.92 :
/// ((c + 0.055) / 1.055)^2.4, in double, rounded to float.
inline const std::array<float, 256>& srgbDecodeTable() {
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (int b = 0; b < 256; ++b) {
            const double c = double(b) / 255.0;
            t[std::size_t(b)] =
                float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
        }
        return t;
    }();
    return table;
}
inline float srgbToLinear(std::uint8_t b) { return srgbDecodeTable()[b]; }

/// One level of a mip chain: linear RGBA texels, row 0 = texture coordinate v = 0.
struct MipLevel {
    int width = 0, height = 0;
    std::vector<glm::vec4> texels;  ///< width · height, row-major (unless `bytes`)
    /// Level 0 of a chain: the image's own RGBA8 bytes (not copied: the image outlives the
    /// chain), decoded as they are read (sRGB through srgbDecodeTable(), or `linear` data as
    /// byte / 255) into the very floats `texels` would hold. A 2048² texture is 16 MiB of
    /// bytes where its decoded level 0 was 64 MiB of floats, written once per render.
    const std::uint8_t* bytes = nullptr;
    const float* srgb = nullptr;  ///< srgbDecodeTable(), or null for a `linear` texture
    glm::vec4 at(int i, int j) const {
        const std::size_t k = std::size_t(j) * width + i;
        if (!bytes) return texels[k];
        const std::uint8_t* p = bytes + 4 * k;
        if (!srgb)
            return glm::vec4(float(p[0]) / 255.0f, float(p[1]) / 255.0f, float(p[2]) / 255.0f,
                             float(p[3]) / 255.0f);
        return glm::vec4(srgb[p[0]], srgb[p[1]], srgb[p[2]], float(p[3]) / 255.0f);
    }
};

/// A texture's decoded image and (when built with mipmaps) its box-filtered levels.
struct MipChain {
    std::vector<MipLevel> levels;  ///< levels[0] = the image; empty for an empty image
    int lastLevel() const { return int(levels.size()) - 1; }
};

/// Level k + 1 from level k: the 2×2 box average in linear space (see the header comment).
inline MipLevel downsampleLevel(const MipLevel& src) {
    MipLevel dst;
    dst.width = std::max(1, src.width / 2);
    dst.height = std::max(1, src.height / 2);
    dst.texels.resize(std::size_t(dst.width) * dst.height);
    for (int j = 0; j < dst.height; ++j) {
        const int j0 = std::min(2 * j, src.height - 1), j1 = std::min(2 * j + 1, src.height - 1);
        for (int i = 0; i < dst.width; ++i) {
            const int i0 = std::min(2 * i, src.width - 1), i1 = std::min(2 * i + 1, src.width - 1);
            dst.texels[std::size_t(j) * dst.width + i] =
                ((src.at(i0, j0) + src.at(i1, j0)) + (src.at(i0, j1) + src.at(i1, j1))) * 0.25f;
        }
    }
    return dst;
}

/// The mip chain of an sRGB RGBA8 image (or, `linear`, a data texture's bytes as byte / 255:
/// scene.h Texture::linear): level 0 reads `image`'s bytes as they are (MipLevel::bytes; the
/// image must outlive the chain) and, if `mipmaps`, every level down to 1×1 is built.
inline MipChain buildMipChain(const Image& image, bool mipmaps, bool linear = false) {
    MipChain chain;
    if (image.empty()) return chain;
    MipLevel base;
    base.width = image.width, base.height = image.height;
    base.bytes = image.rgba.data();
    base.srgb = linear ? nullptr : srgbDecodeTable().data();
    chain.levels.push_back(std::move(base));
    while (mipmaps && (chain.levels.back().width > 1 || chain.levels.back().height > 1)) {
        MipLevel next = downsampleLevel(chain.levels.back());
        chain.levels.push_back(std::move(next));
    }
    return chain;
}
/// A temporary image would leave level 0 reading freed bytes.
MipChain buildMipChain(const Image&& image, bool mipmaps, bool linear = false) = delete;

/// Texel index i wrapped into [0, n) (GL §8.14.2 Table 8.20).
inline int wrapTexel(std::int64_t i, int n, TextureWrap mode) {
    switch (mode) {
        case TextureWrap::ClampToEdge: return int(std::clamp<std::int64_t>(i, 0, n - 1));
        case TextureWrap::MirroredRepeat: {
            const std::int64_t period = 2 * std::int64_t(n);
            std::int64_t m = i % period;
            if (m < 0) m += period;
            const std::int64_t a = m - n;
            const std::int64_t mirrored = a >= 0 ? a : -(1 + a);
            return int((n - 1) - mirrored);
        }
        case TextureWrap::Repeat:
        default: {
            std::int64_t m = i % n;
            if (m < 0) m += n;
            return int(m);
        }
    }
}

/// floor(x) as an integer, with non-finite x mapped to 0 and |x| limited to 2^40 (every wrap
/// mode gives the same texel for such indices as for the exact ones, for textures ≤ 2^16).
inline std::int64_t floorIndex(float x) {
    if (!std::isfinite(x)) return 0;
    return std::int64_t(std::floor(std::clamp(x, -0x1p40f, 0x1p40f)));
}

/// GL_NEAREST on one level.
inline glm::vec4 sampleNearest(const MipLevel& level, glm::vec2 uv, const TextureSampler& s) {
    const int i = wrapTexel(floorIndex(uv.x * float(level.width)), level.width, s.wrapS);
    const int j = wrapTexel(floorIndex(uv.y * float(level.height)), level.height, s.wrapT);
    return level.at(i, j);
}

/// GL_LINEAR (bilinear) on one level.
inline glm::vec4 sampleBilinear(const MipLevel& level, glm::vec2 uv, const TextureSampler& s) {
    const float uf = uv.x * float(level.width) - 0.5f, vf = uv.y * float(level.height) - 0.5f;
    const std::int64_t i0 = floorIndex(uf), j0 = floorIndex(vf);
    const float a = std::isfinite(uf) ? uf - std::floor(uf) : 0.0f;
    const float b = std::isfinite(vf) ? vf - std::floor(vf) : 0.0f;
    const int ia = wrapTexel(i0, level.width, s.wrapS),
              ib = wrapTexel(i0 + 1, level.width, s.wrapS);
    const int ja = wrapTexel(j0, level.height, s.wrapT);
    const int jb = wrapTexel(j0 + 1, level.height, s.wrapT);
    return ((level.at(ia, ja) * ((1.0f - a) * (1.0f - b)) + level.at(ib, ja) * (a * (1.0f - b))) +
            level.at(ia, jb) * ((1.0f - a) * b)) +
           level.at(ib, jb) * (a * b);
}

inline glm::vec4 sampleLevel(const MipLevel& level, glm::vec2 uv, const TextureSampler& s,
                             TextureFilter filter) {
    return filter == TextureFilter::Linear ? sampleBilinear(level, uv, s)
                                           : sampleNearest(level, uv, s);
}

/// Screen-space derivatives of the texture coordinates at a fragment, per window pixel.
struct UvDerivatives {
    glm::vec2 dx{0.0f};  ///< ∂(u, v)/∂x
    glm::vec2 dy{0.0f};  ///< ∂(u, v)/∂y
};

/// Derivatives of a perspective-correct attribute u = Σ p_i u_i / Σ p_i with p_i = l_i · q_i
/// (l_i the screen-space barycentrics, affine in window x, y; q_i = 1/w_i), given the gradients
/// gx_i = ∂l_i/∂x, gy_i = ∂l_i/∂y (per pixel), the fragment's `uv` and inv = 1 / Σ p_i:
/// ∂u/∂x = (Σ gx_i q_i u_i − u · Σ gx_i q_i) · inv, likewise for y. Exact derivatives of the
/// interpolated coordinate (not finite differences over a 2×2 quad, which GL allows).
inline UvDerivatives uvDerivatives(const float gx[3], const float gy[3], const float q[3],
                                   const glm::vec2 uvi[3], glm::vec2 uv, float inv) {
    UvDerivatives d;
    const float bx = (gx[0] * q[0] + gx[1] * q[1]) + gx[2] * q[2];
    const float by = (gy[0] * q[0] + gy[1] * q[1]) + gy[2] * q[2];
    for (int c = 0; c < 2; ++c) {
        const float ax =
            ((gx[0] * q[0]) * uvi[0][c] + (gx[1] * q[1]) * uvi[1][c]) + (gx[2] * q[2]) * uvi[2][c];
        const float ay =
            ((gy[0] * q[0]) * uvi[0][c] + (gy[1] * q[1]) * uvi[1][c]) + (gy[2] * q[2]) * uvi[2][c];
        d.dx[c] = (ax - uv[c] * bx) * inv;
        d.dy[c] = (ay - uv[c] * by) * inv;
    }
    return d;
}

/// λ = log2 ρ, ρ the GL scale factor for level 0 of `width` × `height` texels (see 5. above).
/// −inf for zero derivatives (magnification); a non-finite ρ² gives λ = 0.
inline float textureLod(const UvDerivatives& d, int width, int height) {
    const float w = float(width), h = float(height);
    const float xu = d.dx.x * w, xv = d.dx.y * h, yu = d.dy.x * w, yv = d.dy.y * h;
    const float rho2 = std::max(xu * xu + xv * xv, yu * yu + yv * yv);
    if (!std::isfinite(rho2)) return 0.0f;
    return 0.5f * std::log2(rho2);
}

/// Whether λ selects magnification: λ ≤ c, c = 0.5 for magFilter Linear with minFilter Nearest
/// and mipmaps (GL's NEAREST_MIPMAP_NEAREST / LINEAR case of §8.15), else 0.
inline bool samplerMagnifies(const TextureSampler& s, float lambda) {
    const float c =
        (s.mipmaps && s.magFilter == TextureFilter::Linear && s.minFilter == TextureFilter::Nearest)
            ? 0.5f
            : 0.0f;
    return !(lambda > c);
}

/// The texture's linear RGBA at `uv` for level of detail λ (see 6. above). An empty chain
/// samples as opaque white (the material's factors alone).
inline glm::vec4 sampleTexture(const MipChain& chain, const TextureSampler& s, glm::vec2 uv,
                               float lambda) {
    if (chain.levels.empty()) return glm::vec4(1.0f);
    const MipLevel& base = chain.levels[0];
    if (samplerMagnifies(s, lambda)) return sampleLevel(base, uv, s, s.magFilter);
    const int q = chain.lastLevel();
    if (!s.mipmaps || q == 0) return sampleLevel(base, uv, s, s.minFilter);
    if (s.minFilter == TextureFilter::Nearest) {
        const int d = lambda <= 0.5f ? 0 : int(std::min(std::ceil(lambda + 0.5f) - 1.0f, float(q)));
        return sampleNearest(chain.levels[std::size_t(std::min(d, q))], uv, s);
    }
    if (!(lambda < float(q))) return sampleBilinear(chain.levels[std::size_t(q)], uv, s);
    const float fl = std::floor(lambda);
    const int d = int(fl);
    const float f = lambda - fl;
    const glm::vec4 t1 = sampleBilinear(chain.levels[std::size_t(d)], uv, s);
    const glm::vec4 t2 = sampleBilinear(chain.levels[std::size_t(d + 1)], uv, s);
    return t1 * (1.0f - f) + t2 * f;
}

}  // namespace mvr

// Scalar loops of the projection kernels: the scalar path, and the tails of the SIMD paths.
#pragma once

#include "../pipeline.h"

namespace mvr::raster::detail {

inline void projectYZWTail(const float* y, const float* z, const float* w, std::size_t n,
                           float height, std::uint8_t* code, float* q, std::int32_t* sy, float* zw) {
    for (std::size_t i = 0; i < n; ++i) {
        code[i] = outcodeYZW(y[i], z[i], w[i]);
        q[i] = 1.0f / w[i];
        sy[i] = code[i] & kClipYZW ? 0 : snapY(y[i], q[i], height);
        zw[i] = windowDepth(z[i], q[i]);
    }
}

inline void projectXTail(const float* x, const float* w, const float* q, std::size_t n, float width,
                         std::uint8_t* code, std::int32_t* sx) {
    for (std::size_t i = 0; i < n; ++i) {
        code[i] = outcodeX(x[i], w[i]);
        sx[i] = code[i] & kClipX ? 0 : snapX(x[i], q[i], width);
    }
}

}  // namespace mvr::raster::detail

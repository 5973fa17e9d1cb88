#include "spirv.h"

namespace mvr::vk::detail {

namespace {
// glslc -mfmt=c writes each module as a brace-enclosed list of 32-bit words.
const std::uint32_t kFlatPass[] =
#include "scene_flat_pass.vert.inc"
    ;
const std::uint32_t kFlatMultiview[] =
#include "scene_flat_multiview.vert.inc"
    ;
const std::uint32_t kFlatLayer[] =
#include "scene_flat_layer.vert.inc"
    ;
const std::uint32_t kVertexPass[] =
#include "scene_vertex_pass.vert.inc"
    ;
const std::uint32_t kVertexMultiview[] =
#include "scene_vertex_multiview.vert.inc"
    ;
const std::uint32_t kVertexLayer[] =
#include "scene_vertex_layer.vert.inc"
    ;
const std::uint32_t kPixelPass[] =
#include "scene_pixel_pass.vert.inc"
    ;
const std::uint32_t kPixelMultiview[] =
#include "scene_pixel_multiview.vert.inc"
    ;
const std::uint32_t kPixelLayer[] =
#include "scene_pixel_layer.vert.inc"
    ;
const std::uint32_t kFlatFrag[] =
#include "scene_flat.frag.inc"
    ;
const std::uint32_t kVertexFrag[] =
#include "scene_vertex.frag.inc"
    ;
const std::uint32_t kPixelFrag[] =
#include "scene_pixel.frag.inc"
    ;
using Words = std::span<const std::uint32_t>;

}  // namespace

std::span<const std::uint32_t> sceneVertexSpirv(Shading shading, ViewSource views) {
    switch (shading) {
        case Shading::Flat:
            return views == ViewSource::Pass        ? Words(kFlatPass)
                   : views == ViewSource::Multiview ? Words(kFlatMultiview)
                                                    : Words(kFlatLayer);
        case Shading::Vertex:
            return views == ViewSource::Pass        ? Words(kVertexPass)
                   : views == ViewSource::Multiview ? Words(kVertexMultiview)
                                                    : Words(kVertexLayer);
        case Shading::Pixel: break;
    }
    return views == ViewSource::Pass        ? Words(kPixelPass)
           : views == ViewSource::Multiview ? Words(kPixelMultiview)
                                            : Words(kPixelLayer);
}

std::span<const std::uint32_t> sceneFragmentSpirv(Shading shading) {
    switch (shading) {
        case Shading::Flat: return kFlatFrag;
        case Shading::Vertex: return kVertexFrag;
        case Shading::Pixel: break;
    }
    return kPixelFrag;
}

}  // namespace mvr::vk::detail

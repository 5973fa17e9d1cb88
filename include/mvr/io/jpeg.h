// mvr/io/jpeg.h — the JPEG decoder (libjpeg-turbo): textures and sky maps (scene_io.h) and
// mvr::composite's JPS / MPO readers. Part of mvr::io; the encoder (JPEG, JPS, MPO) stays in
// mvr::composite (mvr/composite/jpeg.h), which re-exports decodeJpeg as
// mvr::composite::decodeJpeg.
//
// libjpeg decodes every JPEG flavour (progressive, grayscale, restart markers) and reports
// corrupt or truncated data, which mvr turns into an error instead of libjpeg's gray fill
// ("never a silently wrong image").
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "mvr/core/image.h"
#include "mvr/core/status.h"

namespace mvr {

/// Decodes a JPEG (any libjpeg-supported kind except CMYK) to RGBA8 (alpha 255).
/// `what` names the source in messages (a path). Errors: Input for data that is not JPEG,
/// corrupt or truncated; Unsupported for CMYK/YCCK.
Result<Image> decodeJpeg(std::span<const std::uint8_t> data, const std::string& what);

}  // namespace mvr

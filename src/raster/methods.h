// src/raster/methods.h — the soft backend's two methods (see soft_backend.h).
#pragma once

#include <memory>
#include <span>

#include "frame.h"

namespace mvr::raster::detail {

/// Buffers a method keeps between renders (vertex arrays, bins), so that a frame does not pay
/// for allocating and zeroing them.
struct MethodScratch {
    virtual ~MethodScratch() = default;
};

/// N independent single-view renders into `targets` (sized, not cleared: every band's rows are
/// cleared by the task that draws them, clearRows). Adds stage times.
void renderMultipass(FrameContext& f, std::span<const Target> targets, StageTimes& times,
                     std::unique_ptr<MethodScratch>& scratch);

/// The unified N-view pipeline into `targets` (sized, not cleared: clearRows, per band). Adds
/// stage times.
void renderUnified(FrameContext& f, std::span<const Target> targets, StageTimes& times,
                   std::unique_ptr<MethodScratch>& scratch);

}  // namespace mvr::raster::detail

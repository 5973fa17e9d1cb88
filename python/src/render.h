// python/src/render.h — mvr.render() and mvr.render_sequence() (render.cpp): a recipe from the
// keywords (keywords.h), prepared once (session::prepare(), its backend and surfaces), then one
// frame or one per frame of a sequence, each returned as a RenderResult whose arrays own the
// memory the backend rendered into, and written by session::writeOutputs() when output= is given.
#pragma once

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "keywords.h"
#include "mvr/backends.h"
#include "mvr/core/image.h"
#include "mvr/session/sequence.h"

namespace mvr::python {

// ---- arrays that own C++ buffers -------------------------------------------------------------
template <class V>
py::array adopt(V&& data, std::vector<py::ssize_t> shape) {
    using E = typename std::decay_t<V>::value_type;
    auto* owner = new std::decay_t<V>(std::move(data));
    py::capsule base(owner, [](void* p) { delete static_cast<std::decay_t<V>*>(p); });
    return py::array_t<E>(shape, owner->data(), base);
}


/// An (H, W, 4) array owning the image's pixels.
py::array imageArray(Image&& image);

/// Renders on a GPU backend (one driver context per thread) are serialised by this lock.
std::mutex& gpuMutex();

struct RenderResult {
    py::object color, depth, method, note, backend, rig, comfort, composites, scene, triangles;
    py::object size, shading, elapsedMs, written;
    py::object views;  ///< per view cameras (mvr/session/cameras.h)
    /// Per view, the projection's (P[2][2], P[3][2]): result.distance from .depth on access
    /// (computed when asked: an array as large as the depth).
    std::vector<std::pair<float, float>> depthToDistance;
    py::object frame = py::none();  ///< the frame of a sequence (None: a still)
    int copiedViews = 0;  ///< images the backend left outside the output block (copied in)
};

/// Composes `views` as `format`: an array for image formats, bytes for jps / mpo. Where the
/// backend composes when one is given.
py::object composeOne(const std::string& format, std::vector<Image>& views,
                      const composite::ComposeOptions& options, const Backend* backend, bool gpu);

/// mvr.render(models, **keywords).
RenderResult render(const py::object& models, const py::kwargs& kwargs);

struct Job;

/// mvr.render_sequence(models, **keywords): an iterator of one RenderResult per frame.
class Sequence {
public:
    Sequence(const py::object& models, const py::kwargs& kwargs);
    ~Sequence();
    /// The next frame's result; py::stop_iteration after the last.
    RenderResult next();
    /// The frames it renders (frame_range, shard), in order.
    std::vector<int> frames() const { return mPlan.todo; }
    std::size_t size() const { return mPlan.todo.size(); }

private:
    std::unique_ptr<Job> mJob;
    session::SequencePlan mPlan;
    std::unique_ptr<session::FrameStepper> mStepper;
    std::size_t mNext = 0;
};

}  // namespace mvr::python

// python/src/keywords.h — the keywords of mvr.render() / mvr.compose() read into the session
// library's RenderRecipe (mvr/session/recipe.h) and composite::ComposeOptions, without any
// command-line code: each keyword is an option of `mvr render` / `mvr compose` with dashes as
// underscores, checked for its type here (ParameterError) and for its value here or by
// session::prepare() (ValueError, with the option's message).
#pragma once

#include <string>

#include <pybind11/pybind11.h>

#include "mvr/composite/compose.h"
#include "mvr/core/status.h"
#include "mvr/session/recipe.h"

namespace mvr::python {

namespace py = pybind11;

/// mvr.ParameterError(TypeError, ValueError), created by the module.
extern PyObject* gParameterError;

/// A keyword of the wrong type or an unknown keyword: ParameterError.
[[noreturn]] void throwParameter(const std::string& message);
/// A Status as its Python exception: ValueError (usage), FileNotFoundError / OSError (input,
/// output), RuntimeError (anything else), with the library's message.
[[noreturn]] void throwStatus(const Status& s);

template <class T>
T check(Result<T>&& r) {
    if (!r) throwStatus(r.status());
    return std::move(r).value();
}

/// What mvr.render() was asked: the recipe (models, keywords) and whether `quiet` was given.
struct RenderKeywords {
    session::RenderRecipe recipe;
    bool quiet = false;
};
/// `sequence`: also the keywords of a sequence (frames, orbit, camera_path, frame_range, shard,
/// fps; mvr.render_sequence()).
RenderKeywords renderKeywords(const py::object& models, const py::dict& kwargs, bool sequence);

/// What mvr.compose() was asked: the composite options and `output` (empty: none).
struct ComposeKeywords {
    composite::ComposeOptions compose;
    std::string output;
    bool quiet = false;
};
ComposeKeywords composeKeywords(const py::dict& kwargs);

/// A file path keyword (str or os.PathLike), else ParameterError naming `what`.
std::string pathOf(const py::handle& p, const char* what);

}  // namespace mvr::python

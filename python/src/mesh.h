// python/src/mesh.h — mvr.Mesh: a mesh from numpy arrays, rendered with the model files
// (session::InlineModel).
#pragma once

#include <pybind11/pybind11.h>

#include "mvr/session/recipe.h"

namespace mvr::python {

namespace py = pybind11;

/// What an mvr.Mesh holds.
struct PyMesh {
    session::InlineModel model;
};

/// Registers mvr.Mesh in the module.
void defineMesh(py::module_& m);

}  // namespace mvr::python

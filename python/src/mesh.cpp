// python/src/mesh.cpp — mvr.Mesh(vertices, faces, normals=None, uvs=None, colors=None,
// texture=None, name="mesh", placement=None): numpy arrays checked (shapes, finite values,
// index range, colours 0..1; ValueError naming the array) and copied once into the library's
// Mesh.
#include "mesh.h"

#include <cmath>
#include <cstring>

#include <fmt/core.h>
#include <pybind11/numpy.h>

#include "keywords.h"
#include "mvr/core/mesh.h"

namespace mvr::python {
namespace {

[[noreturn]] void bad(const std::string& message) { throwStatus(usageError(message)); }

std::string shapeOf(const py::array& a) {
    std::string s = "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i)
        s += (i ? ", " : "") + std::to_string(a.shape(i));
    return s + (a.ndim() == 1 ? ",)" : ")");
}

/// `a` as a C-contiguous float32 array of shape (n, cols) (any numeric dtype converted).
py::array_t<float, py::array::c_style | py::array::forcecast> floats(const py::object& a,
                                                                     const char* what, int cols,
                                                                     py::ssize_t rows = -1) {
    py::array_t<float, py::array::c_style | py::array::forcecast> arr;
    try {
        arr = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
    } catch (const py::error_already_set&) {
        arr = {};
    }
    if (!arr) bad(fmt::format("{}: expected a numeric array", what));
    if (arr.ndim() != 2 || arr.shape(1) != cols)
        bad(fmt::format("{}: expected shape (N, {}), got {}", what, cols, shapeOf(arr)));
    if (rows >= 0 && arr.shape(0) != rows)
        bad(fmt::format("{}: {} rows for {} vertices (expected one per vertex)", what,
                        arr.shape(0), rows));
    const float* p = arr.data();
    for (py::ssize_t i = 0; i < arr.size(); ++i) {
        if (!std::isfinite(p[i]))
            bad(fmt::format("{}: row {} is not finite", what, i / cols));
    }
    return arr;
}

/// colors: (N, 3) or (N, 4); floats are linear 0..1 (glTF's COLOR_0), uint8 are sRGB-encoded
/// bytes as images and trimesh's vertex colours hold them (decoded, mesh.h).
std::vector<glm::vec4> vertexColors(const py::object& colors, py::ssize_t n) {
    py::array raw = py::array::ensure(colors);
    if (!raw) bad("colors: expected a numeric array");
    const int cols = raw.ndim() == 2 ? int(raw.shape(1)) : 0;
    if (raw.ndim() != 2 || (cols != 3 && cols != 4))
        bad(fmt::format("colors: expected shape (N, 3) or (N, 4), got {}", shapeOf(raw)));
    if (raw.shape(0) != n)
        bad(fmt::format("colors: {} rows for {} vertices (expected one per vertex)", raw.shape(0),
                        n));
    std::vector<glm::vec4> out(std::size_t(n), glm::vec4(1.0f));
    if (raw.dtype().kind() == 'u' && raw.itemsize() == 1) {
        auto bytes = py::array_t<std::uint8_t, py::array::c_style>::ensure(raw);
        const std::uint8_t* p = bytes.data();
        for (std::size_t i = 0; i < out.size(); ++i) {
            glm::vec4 c(1.0f);
            for (int k = 0; k < cols; ++k) c[k] = float(p[std::size_t(cols) * i + k]) / 255.0f;
            out[i] = decodeSrgbColor(c);
        }
        return out;
    }
    if (raw.dtype().kind() != 'f')
        bad(fmt::format("colors: expected floats (linear 0..1) or uint8 (sRGB), got dtype {}",
                        std::string(py::str(raw.dtype()))));
    auto f = floats(colors, "colors", cols, n);
    const float* p = f.data();
    for (std::size_t i = 0; i < out.size(); ++i) {
        for (int k = 0; k < cols; ++k) {
            const float v = p[std::size_t(cols) * i + k];
            if (!(v >= 0.0f && v <= 1.0f))
                bad(fmt::format("colors: row {} has {} (expected 0..1)", i, v));
            out[i][k] = v;
        }
    }
    return out;
}

PyMesh makeMesh(const py::object& vertices, const py::object& faces, const py::object& normals,
                const py::object& uvs, const py::object& colors, const py::object& texture,
                const std::string& name, const py::object& placement) {
    auto pos = floats(vertices, "vertices", 3);
    const py::ssize_t n = pos.shape(0);
    if (n < 3) bad(fmt::format("vertices: {} rows (expected at least 3)", n));
    if (n > (py::ssize_t(1) << 31)) bad("vertices: more than 2^31 rows");
    py::array_t<long long, py::array::c_style | py::array::forcecast> idx;
    {
        py::array raw = py::array::ensure(faces);
        if (!raw) bad("faces: expected an integer array");
        if (raw.dtype().kind() != 'i' && raw.dtype().kind() != 'u')
            bad(fmt::format("faces: expected integers, got dtype {}",
                            std::string(py::str(raw.dtype()))));
        idx = py::array_t<long long, py::array::c_style | py::array::forcecast>::ensure(raw);
    }
    if (idx.ndim() != 2 || idx.shape(1) != 3)
        bad(fmt::format("faces: expected shape (M, 3), got {}", shapeOf(idx)));
    if (idx.shape(0) < 1) bad("faces: no triangles");
    auto m = std::make_shared<Mesh>();
    m->name = name;
    m->positions.resize(std::size_t(n));
    std::memcpy(m->positions.data(), pos.data(), std::size_t(n) * 3 * sizeof(float));
    const long long* f = idx.data();
    m->indices.resize(std::size_t(idx.size()));
    for (py::ssize_t i = 0; i < idx.size(); ++i) {
        if (f[i] < 0 || f[i] >= n)
            bad(fmt::format("faces: row {} has index {} (expected 0..{})", i / 3, f[i], n - 1));
        m->indices[std::size_t(i)] = std::uint32_t(f[i]);
    }
    if (!normals.is_none()) {
        auto nrm = floats(normals, "normals", 3, n);
        m->normals.resize(std::size_t(n));
        std::memcpy(m->normals.data(), nrm.data(), std::size_t(n) * 3 * sizeof(float));
        for (glm::vec3& v : m->normals) {
            const float len = glm::length(v);
            if (!(len > 0.0f)) bad("normals: a zero-length normal");
            v /= len;
        }
    } else {
        computeSmoothNormals(*m);
    }
    if (!uvs.is_none()) {
        auto uv = floats(uvs, "uvs", 2, n);
        m->texcoords.resize(std::size_t(n));
        std::memcpy(m->texcoords.data(), uv.data(), std::size_t(n) * 2 * sizeof(float));
    }
    if (!colors.is_none()) m->colors = vertexColors(colors, n);
    if (Status s = validateMesh(*m, name); !s) throwStatus(s);
    PyMesh out;
    out.model.name = name;
    out.model.mesh = std::move(m);
    if (!texture.is_none()) {
        py::array raw = py::array::ensure(texture);
        if (!raw || raw.dtype().kind() != 'u' || raw.itemsize() != 1 || raw.ndim() != 3 ||
            (raw.shape(2) != 3 && raw.shape(2) != 4))
            bad("texture: expected a uint8 array of shape (H, W, 3) or (H, W, 4)");
        if (uvs.is_none()) bad("texture: needs uvs (one per vertex)");
        auto tex = py::array_t<std::uint8_t, py::array::c_style>::ensure(raw);
        const int h = int(tex.shape(0)), w = int(tex.shape(1)), c = int(tex.shape(2));
        if (h < 1 || w < 1 || h > 16384 || w > 16384)
            bad(fmt::format("texture: {}x{} pixels (expected 1..16384 each)", w, h));
        Image img(w, h);
        const std::uint8_t* src = tex.data();
        for (std::size_t i = 0; i < std::size_t(w) * std::size_t(h); ++i) {
            img.rgba[4 * i] = src[c * i], img.rgba[4 * i + 1] = src[c * i + 1];
            img.rgba[4 * i + 2] = src[c * i + 2];
            img.rgba[4 * i + 3] = c == 4 ? src[c * i + 3] : 255;
        }
        out.model.texture = std::move(img);
    }
    if (!placement.is_none()) out.model.placement = py::str(placement);
    return out;
}

}  // namespace

void defineMesh(py::module_& m) {
    py::class_<PyMesh>(m, "Mesh",
                       "A triangle mesh from arrays, rendered with the model files: "
                       "mvr.render([path, mesh, ...]).")
        .def(py::init(&makeMesh), py::arg("vertices"), py::arg("faces"),
             py::arg("normals") = py::none(), py::arg("uvs") = py::none(),
             py::arg("colors") = py::none(), py::arg("texture") = py::none(),
             py::arg("name") = "mesh", py::arg("placement") = py::none(),
             "vertices float (N, 3); faces int (M, 3), counter-clockwise = front; normals (N, 3) "
             "(default: smooth, area-weighted); uvs (N, 2) with texture uint8 (H, W, 3|4) as the "
             "base colour; colors (N, 3|4) per vertex, float linear 0..1 or uint8 sRGB, multiply "
             "the base colour (white for a mesh with colours); placement \"X,Y,Z[,SCALE[,YAW]]\" "
             "as a model file's FILE@.... The arrays are copied once.")
        .def_property_readonly("name", [](const PyMesh& p) { return p.model.name; })
        .def_property_readonly("vertex_count",
                               [](const PyMesh& p) { return p.model.mesh->positions.size(); })
        .def_property_readonly("triangle_count",
                               [](const PyMesh& p) { return p.model.mesh->triangleCount(); });
}

}  // namespace mvr::python

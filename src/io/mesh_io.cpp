// mesh_io.cpp — model files as one mesh (loadMesh) and the load-time locality pass (mesh_io.h).
#include "mvr/io/mesh_io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string_view>
#include <fstream>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/core.h>
#include <meshoptimizer.h>

#include "model_guard.h"
#include "mvr/core/input_file.h"
#include "ply.h"

namespace mvr {

void optimizeMeshLocality(Mesh& mesh) {
    if (mesh.indices.empty()) return;
    const std::size_t vertexCount = mesh.positions.size();
    meshopt_optimizeVertexCache(mesh.indices.data(), mesh.indices.data(), mesh.indices.size(),
                                vertexCount);
    std::vector<unsigned int> remap(vertexCount);
    const std::size_t used = meshopt_optimizeVertexFetchRemap(remap.data(), mesh.indices.data(),
                                                              mesh.indices.size(), vertexCount);
    meshopt_remapIndexBuffer(mesh.indices.data(), mesh.indices.data(), mesh.indices.size(),
                             remap.data());
    auto remapStream = [&](auto& stream) {
        if (stream.empty()) return;
        using T = typename std::decay_t<decltype(stream)>::value_type;
        std::vector<T> out(used);
        meshopt_remapVertexBuffer(out.data(), stream.data(), vertexCount, sizeof(T), remap.data());
        stream = std::move(out);
    };
    remapStream(mesh.positions);
    remapStream(mesh.normals);
    remapStream(mesh.texcoords);
    remapStream(mesh.colors);
    remapStream(mesh.tangents);
    remapStream(mesh.baseTangents);
    remapStream(mesh.joints);
    remapStream(mesh.weights);
    remapStream(mesh.joints1);
    remapStream(mesh.weights1);
    remapStream(mesh.basePositions);
    remapStream(mesh.baseNormals);
    for (MorphTarget& t : mesh.morphTargets) {
        remapStream(t.positions);
        remapStream(t.normals);
    }
}

namespace {

/// `srgbColors`: the file's vertex colours are sRGB-encoded (every format but glTF, whose
/// COLOR_0 is linear): decoded as mesh.h's Mesh::colors says.
void appendNode(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent, Mesh& out,
                bool& allHaveNormals, bool srgbColors) {
    const aiMatrix4x4 transform = parent * node.mTransformation;
    aiMatrix3x3 normalMatrix(transform);
    normalMatrix.Inverse().Transpose();
    for (unsigned m = 0; m < node.mNumMeshes; ++m) {
        if (node.mMeshes[m] >= scene.mNumMeshes) continue;
        const aiMesh& mesh = *scene.mMeshes[node.mMeshes[m]];
        if (!(mesh.mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
        const auto base = static_cast<std::uint32_t>(out.positions.size());
        const bool hasNormals = mesh.HasNormals();
        allHaveNormals = allHaveNormals && hasNormals;
        const bool hasUv = mesh.HasTextureCoords(0);
        const bool hasColor = mesh.HasVertexColors(0);
        for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
            if (hasColor) {
                const aiColor4D& c = mesh.mColors[0][v];
                const glm::vec4 rgba(c.r, c.g, c.b, c.a);
                out.colors.push_back(srgbColors ? decodeSrgbColor(rgba)
                                                : glm::clamp(rgba, glm::vec4(0.0f), glm::vec4(1.0f)));
            } else {
                out.colors.emplace_back(1.0f);
            }
            const aiVector3D p = transform * mesh.mVertices[v];
            out.positions.emplace_back(p.x, p.y, p.z);
            if (hasNormals) {
                const aiVector3D n = (normalMatrix * mesh.mNormals[v]).NormalizeSafe();
                out.normals.emplace_back(n.x, n.y, n.z);
            } else {
                out.normals.emplace_back(0.0f);
            }
            if (hasUv) {
                out.texcoords.emplace_back(mesh.mTextureCoords[0][v].x,
                                           mesh.mTextureCoords[0][v].y);
            } else {
                out.texcoords.emplace_back(0.0f);
            }
        }
        for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
            const aiFace& face = mesh.mFaces[f];
            if (face.mNumIndices != 3) continue;  // points and lines are not drawn
            for (int k = 0; k < 3; ++k) out.indices.push_back(base + face.mIndices[k]);
        }
    }
    for (unsigned c = 0; c < node.mNumChildren; ++c) {
        appendNode(scene, *node.mChildren[c], transform, out, allHaveNormals, srgbColors);
    }
}

/// What mvr checks in an OBJ's text before assimp reads it: assimp drops NaN vertices and
/// degenerate faces silently and then reports "No meshes remaining", which names neither the
/// line nor the reason. Lines are joined at `\` continuations; CR line ends are accepted.
struct ObjScan {
    Status status;          ///< the first non-finite vertex, by line
    std::size_t faces = 0;  ///< face lines
    bool anyArea = false;   ///< some face has a non-zero area
};

ObjScan scanObj(const std::string& text, const std::string& what) {
    ObjScan scan;
    std::vector<glm::dvec3> vertices;
    std::size_t pos = 0, lineNo = 0;
    std::string line;
    while (pos < text.size()) {
        // One logical line: physical lines joined where one ends in a backslash.
        line.clear();
        const std::size_t firstLine = lineNo + 1;
        for (;;) {
            std::size_t end = text.find('\n', pos);
            if (end == std::string::npos) end = text.size();
            std::string_view piece(text.data() + pos, end - pos);
            ++lineNo;
            pos = end + 1;
            if (!piece.empty() && piece.back() == '\r') piece.remove_suffix(1);
            if (!piece.empty() && piece.back() == '\\' && pos < text.size()) {
                piece.remove_suffix(1);
                line.append(piece).push_back(' ');
                continue;
            }
            line.append(piece);
            break;
        }
        std::size_t i = line.find_first_not_of(" \t");
        if (i == std::string::npos || i + 1 >= line.size()) continue;
        const char c0 = line[i], c1 = line[i + 1];
        if (c0 == 'v' && (c1 == ' ' || c1 == '\t')) {
            glm::dvec3 p(0.0);
            const char* cur = line.c_str() + i + 1;
            for (int k = 0; k < 3; ++k) {
                char* next = nullptr;
                const double value = std::strtod(cur, &next);
                if (next == cur) break;  // assimp's to say what is wrong with it
                if (!std::isfinite(value)) {
                    scan.status = inputError(fmt::format(
                        "{}: line {}: vertex {} has a{} coordinate", what, firstLine,
                        vertices.size() + 1, std::isnan(value) ? " NaN" : "n infinite"));
                    return scan;
                }
                if (std::abs(value) > kMaxCoordinate) {  // mesh.h: framing-safe coordinates
                    scan.status = inputError(fmt::format(
                        "{}: line {}: vertex {} has a coordinate {:g} out of range (at most {:g} "
                        "in magnitude)",
                        what, firstLine, vertices.size() + 1, value, kMaxCoordinate));
                    return scan;
                }
                p[k] = value;
                cur = next;
            }
            vertices.push_back(p);
        } else if (c0 == 'f' && (c1 == ' ' || c1 == '\t')) {
            ++scan.faces;
            if (scan.anyArea) continue;
            std::vector<glm::dvec3> corners;
            const char* cur = line.c_str() + i + 1;
            for (;;) {
                char* next = nullptr;
                const long index = std::strtol(cur, &next, 10);
                if (next == cur) break;
                const long n = long(vertices.size());
                const long resolved = index < 0 ? n + index : index - 1;  // negative: relative
                if (resolved >= 0 && resolved < n) corners.push_back(vertices[resolved]);
                cur = next;
                while (*cur && *cur != ' ' && *cur != '\t') ++cur;  // skip /vt/vn
            }
            glm::dvec3 area(0.0);
            for (std::size_t k = 1; k + 1 < corners.size(); ++k)
                area += glm::cross(corners[k] - corners[0], corners[k + 1] - corners[0]);
            scan.anyArea = glm::length(area) > 0.0;
        }
    }
    return scan;
}

}  // namespace

Result<detail::ModelPreflight> detail::preflightModel(const std::filesystem::path& path,
                                                      const std::string& what) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return inputError(what + ": file not found");
    if (Status s = checkRegularFile(path, what); !s) return s;  // no FIFO, device, directory
    {
        std::ifstream probe(path, std::ios::binary);
        if (!probe) return inputError(what + ": cannot open for reading");
    }
    if (std::filesystem::file_size(path, ec) == 0) return inputError(what + ": file is empty");
    ModelPreflight out;
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    {
        std::ifstream in(path, std::ios::binary);
        char head[8] = {};
        in.read(head, sizeof head);
        const std::string start(head, static_cast<std::size_t>(in.gcount()));
        // Anything else assimp would take as PLY (by the extension or a "ply" start) would
        // reach its PLY reader, which hangs (found by fuzzing, tests/fuzz/regressions/ply/).
        if (!detail::looksLikePly(start) && (ext == ".ply" || start.rfind("ply", 0) == 0))
            return inputError(what + ": malformed PLY: the first line is not \"ply\"");
        if (detail::looksLikePly(start)) {
            out.ply = true;
            return out;
        }
    }
    // OBJ: name the line of a non-finite vertex, and a file whose faces all have zero area,
    // before assimp drops them and says only "No meshes remaining".
    if (ext == ".obj") {
        std::ifstream in(path, std::ios::binary);
        const std::string text((std::istreambuf_iterator<char>(in)),
                               std::istreambuf_iterator<char>());
        const ObjScan obj = scanObj(text, what);
        if (!obj.status) return obj.status;
        out.objAllZeroArea = obj.faces > 0 && !obj.anyArea;
    }
    if (Status s = detail::checkGlbHeader(path, what); !s) return s;
    if (ext == ".gltf" || ext == ".glb") {
        if (Status s = detail::checkGltfBounds(path, what); !s) return s;
    }
    return out;
}

Result<Mesh> loadMesh(const std::filesystem::path& path, std::vector<std::string>* warnings) {
    const std::string what = fmt::format("mvr::loadMesh(): {}", path.string());
    auto pre = detail::preflightModel(path, what);
    if (!pre) return pre.status();
    if (pre->ply) {  // mvr's own reader (assimp's hangs on truncated PLY headers: ply.cpp)
        std::ifstream in(path, std::ios::binary);
        const std::string data((std::istreambuf_iterator<char>(in)),
                               std::istreambuf_iterator<char>());
        auto mesh = detail::loadPly(data, what, warnings);
        if (!mesh) return mesh.status();
        mesh->name = path.filename().string();
        if (Status s = validateMesh(*mesh, what); !s) return s;
        optimizeMeshLocality(*mesh);
        return mesh;
    }

    Assimp::Importer importer;
    importer.SetIOHandler(new detail::ModelIOSystem(path));  // no MTL files: model_guard.h
    // Points and lines are split into meshes of their own (SortByPType) and skipped below, so a
    // file with no faces reports "has no triangles" rather than assimp's "No meshes remaining".
    const aiScene* scene = importer.ReadFile(
        path.string(), aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                           aiProcess_SortByPType | aiProcess_ValidateDataStructure |
                           aiProcess_FindInvalidData);
    if (!scene || !scene->mRootNode) {
        std::string why = importer.GetErrorString();
        if (why.empty()) why = "unknown error";
        if (pre->objAllZeroArea) {
            return inputError(fmt::format("{}: is degenerate (every face has zero area)", what));
        }
        return inputError(fmt::format("{}: not a readable model (assimp: {})", what, why));
    }
    Mesh mesh;
    mesh.name = path.filename().string();
    bool allHaveNormals = true;
    std::string ext = path.extension().string();
    for (char& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    appendNode(*scene, *scene->mRootNode, aiMatrix4x4(), mesh, allHaveNormals,
               ext != ".gltf" && ext != ".glb");
    bool anyUv = false, anyColor = false;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        anyUv = anyUv || scene->mMeshes[m]->HasTextureCoords(0);
        anyColor = anyColor || scene->mMeshes[m]->HasVertexColors(0);
    }
    if (!anyUv) mesh.texcoords.clear();
    if (!anyColor) mesh.colors.clear();
    if (mesh.indices.empty()) return inputError(what + ": has no triangles");
    bool normalsUsable = allHaveNormals;
    for (const glm::vec3& n : mesh.normals) {
        const float len = glm::length(n);
        normalsUsable = normalsUsable && std::isfinite(len) && len > 0.5f;
    }
    if (!normalsUsable) computeSmoothNormals(mesh);
    if (Status s = validateMesh(mesh, what); !s) return s;
    optimizeMeshLocality(mesh);
    return mesh;
}

}  // namespace mvr

// A PLY reader of mvr's own (ascii, binary_little_endian, binary_big_endian).
//
// Why not assimp's: assimp 5.2.5 (Debian 12) hangs on PLY files whose header is truncated and
// aborts on truncated bodies (found by mvr's every-prefix test), and no other PLY library is
// packaged in Debian. PLY is small: header lines, then elements of typed properties. Every read
// below is bounds-checked, counts are checked against the bytes left before anything is
// allocated, and any error is returned as a Status.
#include "ply.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include <fmt/core.h>

namespace mvr::detail {
namespace {

enum class Type { Int8, Uint8, Int16, Uint16, Int32, Uint32, Float32, Float64 };

std::optional<Type> parseType(const std::string& s) {
    if (s == "char" || s == "int8") return Type::Int8;
    if (s == "uchar" || s == "uint8") return Type::Uint8;
    if (s == "short" || s == "int16") return Type::Int16;
    if (s == "ushort" || s == "uint16") return Type::Uint16;
    if (s == "int" || s == "int32") return Type::Int32;
    if (s == "uint" || s == "uint32") return Type::Uint32;
    if (s == "float" || s == "float32") return Type::Float32;
    if (s == "double" || s == "float64") return Type::Float64;
    return std::nullopt;
}

std::size_t typeSize(Type t) {
    switch (t) {
        case Type::Int8:
        case Type::Uint8: return 1;
        case Type::Int16:
        case Type::Uint16: return 2;
        case Type::Int32:
        case Type::Uint32:
        case Type::Float32: return 4;
        case Type::Float64: return 8;
    }
    return 1;
}

struct Property {
    std::string name;
    Type type = Type::Float32;
    bool isList = false;
    Type countType = Type::Uint8;
};

struct Element {
    std::string name;
    std::size_t count = 0;
    std::vector<Property> properties;
};

enum class Encoding { Ascii, BinaryLE, BinaryBE };

/// Reads values from the body, bounds-checked.
class Reader {
public:
    Reader(const std::string& data, std::size_t pos, Encoding enc)
        : mData(data), mPos(pos), mEnc(enc) {}

    bool read(Type t, double& out) {
        if (mEnc == Encoding::Ascii) return readAscii(out);
        const std::size_t n = typeSize(t);
        if (mPos + n > mData.size()) return false;
        unsigned char b[8];
        std::memcpy(b, mData.data() + mPos, n);
        mPos += n;
        const bool little = std::endian::native == std::endian::little;
        if ((mEnc == Encoding::BinaryLE) != little) std::reverse(b, b + n);
        switch (t) {
            case Type::Int8: {
                std::int8_t v;
                std::memcpy(&v, b, 1);
                out = v;
                break;
            }
            case Type::Uint8: {
                out = b[0];
                break;
            }
            case Type::Int16: {
                std::int16_t v;
                std::memcpy(&v, b, 2);
                out = v;
                break;
            }
            case Type::Uint16: {
                std::uint16_t v;
                std::memcpy(&v, b, 2);
                out = v;
                break;
            }
            case Type::Int32: {
                std::int32_t v;
                std::memcpy(&v, b, 4);
                out = v;
                break;
            }
            case Type::Uint32: {
                std::uint32_t v;
                std::memcpy(&v, b, 4);
                out = v;
                break;
            }
            case Type::Float32: {
                float v;
                std::memcpy(&v, b, 4);
                out = v;
                break;
            }
            case Type::Float64: {
                std::memcpy(&out, b, 8);
                break;
            }
        }
        return true;
    }
    std::size_t remaining() const { return mData.size() - mPos; }

private:
    bool readAscii(double& out) {
        while (mPos < mData.size() && std::isspace(static_cast<unsigned char>(mData[mPos]))) ++mPos;
        if (mPos >= mData.size()) return false;
        const char* begin = mData.data() + mPos;
        const char* end = mData.data() + mData.size();
        auto [ptr, ec] = std::from_chars(begin, end, out);
        if (ec != std::errc() || ptr == begin) return false;
        mPos += static_cast<std::size_t>(ptr - begin);
        return true;
    }

    const std::string& mData;
    std::size_t mPos;
    Encoding mEnc;
};

constexpr std::uint32_t kRestart = 0xffffffffu;

/// Triangulates one "tristrips" list: triangle i of a strip (a, b, c) is (a, b, c) for even i
/// and (b, a, c) for odd i (strips alternate winding); kRestart (-1 in the file) starts a new
/// strip; degenerate triangles (two equal indices, the strip's own joints) are dropped.
void appendStrip(const std::vector<std::uint32_t>& strip, std::vector<std::uint32_t>& out) {
    std::size_t start = 0;
    while (start < strip.size()) {
        std::size_t end = start;
        while (end < strip.size() && strip[end] != kRestart) ++end;
        for (std::size_t i = start; i + 2 < end; ++i) {
            std::uint32_t a = strip[i], b = strip[i + 1];
            const std::uint32_t c = strip[i + 2];
            if ((i - start) % 2 == 1) std::swap(a, b);
            if (a == b || b == c || a == c) continue;
            out.insert(out.end(), {a, b, c});
        }
        start = end + 1;
    }
}

}  // namespace

bool looksLikePly(const std::string& head) {
    return head.rfind("ply\n", 0) == 0 || head.rfind("ply\r\n", 0) == 0;
}

Result<Mesh> loadPly(const std::string& data, const std::string& what,
                     std::vector<std::string>* warnings) {
    auto bad = [&](const std::string& why) {
        return inputError(fmt::format("{}: malformed PLY: {}", what, why));
    };
    // Header: lines up to "end_header".
    const std::size_t endHeader = data.find("end_header");
    if (endHeader == std::string::npos) return bad("no end_header line (truncated header?)");
    std::size_t bodyStart = data.find('\n', endHeader);
    if (bodyStart == std::string::npos) return bad("truncated after end_header");
    ++bodyStart;
    std::istringstream header(data.substr(0, endHeader));
    std::string line;
    std::optional<Encoding> encoding;
    std::vector<Element> elements;
    int lineNo = 0;
    while (std::getline(header, line)) {
        ++lineNo;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::istringstream words(line);
        std::string key;
        words >> key;
        if (key.empty() || key == "comment" || key == "obj_info" || key == "ply") continue;
        if (key == "format") {
            std::string fmtName, version;
            words >> fmtName >> version;
            if (fmtName == "ascii")
                encoding = Encoding::Ascii;
            else if (fmtName == "binary_little_endian")
                encoding = Encoding::BinaryLE;
            else if (fmtName == "binary_big_endian")
                encoding = Encoding::BinaryBE;
            else
                return bad(fmt::format("header line {}: unknown format '{}'", lineNo, fmtName));
        } else if (key == "element") {
            Element e;
            long long count = -1;
            words >> e.name >> count;
            if (e.name.empty() || count < 0 || words.fail()) {
                return bad(fmt::format("header line {}: expected 'element NAME COUNT'", lineNo));
            }
            e.count = static_cast<std::size_t>(count);
            elements.push_back(std::move(e));
        } else if (key == "property") {
            if (elements.empty())
                return bad(fmt::format("header line {}: property before any element", lineNo));
            Property p;
            std::string type;
            words >> type;
            if (type == "list") {
                std::string countType, itemType;
                words >> countType >> itemType >> p.name;
                auto ct = parseType(countType);
                auto it = parseType(itemType);
                if (!ct || !it || p.name.empty())
                    return bad(fmt::format("header line {}: bad list property", lineNo));
                p.isList = true;
                p.countType = *ct;
                p.type = *it;
            } else {
                auto t = parseType(type);
                words >> p.name;
                if (!t || p.name.empty())
                    return bad(fmt::format("header line {}: bad property '{}'", lineNo, line));
                p.type = *t;
            }
            elements.back().properties.push_back(p);
        } else if (warnings) {
            warnings->push_back(fmt::format("{}: PLY header line {}: '{}' is not a PLY keyword "
                                            "(a comment without 'comment'?): skipped",
                                            what, lineNo, line));
        }
    }
    if (!encoding) return bad("no format line");

    Mesh mesh;
    Reader reader(data, bodyStart, *encoding);
    bool sawFaces = false;
    for (const Element& e : elements) {
        // Every element takes at least one byte (binary) or two characters (ascii) per property:
        // refuse counts the remaining bytes cannot hold before allocating anything.
        const std::size_t minBytes = std::max<std::size_t>(1, e.properties.size());
        if (e.count > reader.remaining() / minBytes + 1) {
            return bad(
                fmt::format("element '{}' claims {} entries but the file is too short (truncated?)",
                            e.name, e.count));
        }
        const bool isVertex = e.name == "vertex";
        // "tristrips": one list per strip, -1 restarts a strip (the layout of scanned-model
        // archives, e.g. Stanford's and Georgia Tech's).
        const bool isStrips = e.name == "tristrips";
        const bool isFace = e.name == "face" || isStrips;
        int ix = -1, iy = -1, iz = -1, inx = -1, iny = -1, inz = -1, iu = -1, iv = -1, iList = -1;
        int icol[4] = {-1, -1, -1, -1};  // red, green, blue, alpha (MeshLab's and scanners')
        for (int k = 0; k < int(e.properties.size()); ++k) {
            const std::string& n = e.properties[k].name;
            if (e.properties[k].isList) {
                if (n == "vertex_indices" || n == "vertex_index") iList = k;
                continue;
            }
            if (n == "x")
                ix = k;
            else if (n == "y")
                iy = k;
            else if (n == "z")
                iz = k;
            else if (n == "nx")
                inx = k;
            else if (n == "ny")
                iny = k;
            else if (n == "nz")
                inz = k;
            else if (n == "s" || n == "u" || n == "texture_u")
                iu = k;
            else if (n == "t" || n == "v" || n == "texture_v")
                iv = k;
            else if (n == "red" || n == "diffuse_red")
                icol[0] = k;
            else if (n == "green" || n == "diffuse_green")
                icol[1] = k;
            else if (n == "blue" || n == "diffuse_blue")
                icol[2] = k;
            else if (n == "alpha")
                icol[3] = k;
        }
        // Colours: 8- and 16-bit integers are scaled to 0..1, floats taken as 0..1 (clamped);
        // either way sRGB-encoded, as scanners and MeshLab write them (mesh.h Mesh::colors).
        const bool hasColor = isVertex && icol[0] >= 0 && icol[1] >= 0 && icol[2] >= 0;
        float colorScale[4] = {1.0f, 1.0f, 1.0f, 1.0f};
        for (int c = 0; c < 4 && hasColor; ++c) {
            if (icol[c] < 0) continue;
            const Type t = e.properties[std::size_t(icol[c])].type;
            colorScale[c] = (t == Type::Uint8 || t == Type::Int8)     ? 1.0f / 255.0f
                            : (t == Type::Uint16 || t == Type::Int16) ? 1.0f / 65535.0f
                                                                      : 1.0f;
        }
        if (isVertex) {
            if (ix < 0 || iy < 0 || iz < 0) return bad("vertex element lacks x, y or z");
            if (!mesh.positions.empty()) return bad("more than one vertex element");
            mesh.positions.reserve(e.count);
        }
        const bool hasNormals = isVertex && inx >= 0 && iny >= 0 && inz >= 0;
        const bool hasUv = isVertex && iu >= 0 && iv >= 0;
        if (isFace) {
            if (iList < 0) return bad(fmt::format("{} element has no vertex_indices list", e.name));
            sawFaces = true;
        }
        std::vector<double> values(e.properties.size());
        std::vector<std::uint32_t> polygon;
        for (std::size_t i = 0; i < e.count; ++i) {
            for (std::size_t k = 0; k < e.properties.size(); ++k) {
                const Property& p = e.properties[k];
                if (!p.isList) {
                    if (!reader.read(p.type, values[k])) {
                        return bad(fmt::format("{} {} of {}: value missing (truncated?)", e.name, i,
                                               e.count));
                    }
                    continue;
                }
                double countValue = 0;
                if (!reader.read(p.countType, countValue) || !(countValue >= 0) ||
                    countValue > 4294967295.0) {
                    return bad(fmt::format("{} {} of {}: bad list length {}", e.name, i, e.count,
                                           countValue));
                }
                const auto count = static_cast<std::size_t>(countValue);
                // Each item takes its size in binary, and a digit and a separator in ascii:
                // refuse a length the rest of the file cannot hold before reading it.
                const std::size_t itemBytes = *encoding == Encoding::Ascii ? 2 : typeSize(p.type);
                if (count > (reader.remaining() + 1) / itemBytes) {
                    return bad(fmt::format(
                        "{} {} of {}: list of {} items but the file is too short (truncated?)",
                        e.name, i, e.count, count));
                }
                polygon.clear();
                for (std::size_t j = 0; j < count; ++j) {
                    double idx = 0;
                    if (!reader.read(p.type, idx)) {
                        return bad(fmt::format("{} {} of {}: list truncated", e.name, i, e.count));
                    }
                    if (int(k) == iList) {
                        // -1, or 0xffffffff where the list holds uint indices.
                        if (isStrips && (idx == -1 || idx == 4294967295.0)) {
                            polygon.push_back(kRestart);
                            continue;
                        }
                        if (!(idx >= 0) || idx > 4294967294.0) {
                            return bad(fmt::format("{} {}: negative or huge vertex index {}",
                                                   e.name, i, idx));
                        }
                        polygon.push_back(static_cast<std::uint32_t>(idx));
                    }
                }
                if (isStrips && int(k) == iList) {
                    appendStrip(polygon, mesh.indices);
                } else if (isFace && int(k) == iList) {
                    for (std::size_t j = 1; j + 1 < polygon.size(); ++j) {  // fan triangulation
                        mesh.indices.insert(mesh.indices.end(),
                                            {polygon[0], polygon[j], polygon[j + 1]});
                    }
                }
            }
            if (isVertex) {
                if (!std::isfinite(values[ix]) || !std::isfinite(values[iy]) ||
                    !std::isfinite(values[iz])) {
                    return inputError(fmt::format(
                        "{}: vertex {} of {} has a {} coordinate", what, i, e.count,
                        std::isnan(values[ix] + values[iy] + values[iz]) ? "NaN" : "infinite"));
                }
                if (std::abs(values[ix]) > kMaxCoordinate || std::abs(values[iy]) > kMaxCoordinate ||
                    std::abs(values[iz]) > kMaxCoordinate) {
                    return inputError(fmt::format(
                        "{}: vertex {} of {} at ({:g}, {:g}, {:g}) is out of range (coordinates at "
                        "most {:g} in magnitude)",
                        what, i, e.count, values[ix], values[iy], values[iz], kMaxCoordinate));
                }
                mesh.positions.emplace_back(values[ix], values[iy], values[iz]);
                if (hasNormals) mesh.normals.emplace_back(values[inx], values[iny], values[inz]);
                if (hasUv) mesh.texcoords.emplace_back(values[iu], values[iv]);
                if (hasColor) {
                    glm::vec4 c(1.0f);
                    for (int j = 0; j < 4; ++j) {
                        if (icol[j] >= 0) c[j] = float(values[icol[j]]) * colorScale[j];
                    }
                    mesh.colors.push_back(decodeSrgbColor(c));
                }
            }
        }
    }
    if (!sawFaces || mesh.indices.empty())
        return inputError(fmt::format("{}: has no triangles", what));
    bool normalsUsable = !mesh.normals.empty();
    for (glm::vec3& n : mesh.normals) {
        const float len = glm::length(n);
        normalsUsable = normalsUsable && std::isfinite(len) && len > 0.0f;
        if (len > 0.0f) n /= len;
    }
    for (std::uint32_t idx : mesh.indices) {
        if (idx >= mesh.positions.size()) {
            return inputError(fmt::format("{}: index {} out of range for {} vertices", what, idx,
                                          mesh.positions.size()));
        }
    }
    if (!normalsUsable) computeSmoothNormals(mesh);
    return mesh;
}

}  // namespace mvr::detail

// mtl.cpp — mvr's Wavefront MTL reader (see mtl.h).
#include "mvr/io/mtl.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "mvr/core/input_file.h"

namespace mvr {
namespace {

constexpr std::uintmax_t kMaxMtlBytes = 16u << 20;

std::vector<std::string_view> splitWords(std::string_view line) {
    std::vector<std::string_view> words;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
        const std::size_t start = i;
        while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
        if (i > start) words.push_back(line.substr(start, i - start));
    }
    return words;
}

bool parseNumber(std::string_view word, float& out) {
    const char* end = word.data() + word.size();
    const auto [ptr, ec] = std::from_chars(word.data(), end, out);
    return ec == std::errc() && ptr == end && std::isfinite(out);
}

bool isNumber(std::string_view word) {
    float v = 0.0f;
    return parseNumber(word, v);
}

std::string lowercase(std::string_view s) {
    std::string out(s);
    std::transform(out.begin(), out.end(), out.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return out;
}

std::string joinFrom(const std::vector<std::string_view>& words, std::size_t first) {
    std::string out;
    for (std::size_t i = first; i < words.size(); ++i) {
        if (!out.empty()) out += ' ';
        out += words[i];
    }
    return out;
}

/// How many numbers a map_ option takes: a fixed count, or up to 3 (-o, -s, -t).
int optionArgs(const std::string& option, bool& upToThree) {
    upToThree = option == "-o" || option == "-s" || option == "-t";
    if (upToThree) return 3;
    if (option == "-mm") return 2;
    if (option == "-blendu" || option == "-blendv" || option == "-bm" || option == "-boost" ||
        option == "-cc" || option == "-clamp" || option == "-imfchan" || option == "-texres")
        return 1;
    return 0;
}

Result<std::string> readAll(const std::filesystem::path& path, const char* fn) {
    if (Status s = checkRegularFile(path, fmt::format("{}: {}", fn, path.string())); !s) return s;
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec) return inputError(fmt::format("{}: {}: cannot be read", fn, path.string()));
    if (size > kMaxMtlBytes)
        return inputError(fmt::format("{}: {}: is larger than 16 MiB", fn, path.string()));
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    if (!in && !in.eof())
        return inputError(fmt::format("{}: {}: cannot be read", fn, path.string()));
    return text.str();
}

}  // namespace

Result<std::vector<MtlMaterial>> parseMtl(std::string_view text, const std::string& what) {
    std::vector<MtlMaterial> materials;
    int lineNo = 0;
    auto fail = [&](const std::string& problem) {
        return inputError(fmt::format("mvr::parseMtl(): {}:{}: {}", what, lineNo, problem));
    };
    std::size_t pos = 0;
    while (pos <= text.size()) {
        std::size_t end = text.find('\n', pos);
        if (end == std::string_view::npos) end = text.size();
        std::string_view line = text.substr(pos, end - pos);
        pos = end + 1;
        ++lineNo;
        if (const std::size_t hash = line.find('#'); hash != std::string_view::npos)
            line = line.substr(0, hash);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        const std::vector<std::string_view> words = splitWords(line);
        if (words.empty()) continue;
        const std::string key = lowercase(words[0]);
        if (key == "newmtl") {
            if (words.size() < 2) return fail("newmtl without a name");
            materials.push_back({});
            materials.back().name = joinFrom(words, 1);
            continue;
        }
        const bool known = key == "kd" || key == "d" || key == "tr" || key == "map_kd";
        if (!known) continue;
        if (materials.empty()) return fail(fmt::format("{} before any newmtl", words[0]));
        MtlMaterial& m = materials.back();
        if (key == "kd") {
            if (words.size() >= 2 &&
                (lowercase(words[1]) == "spectral" || lowercase(words[1]) == "xyz"))
                return fail("Kd spectral / xyz is not supported (give r g b)");
            if (words.size() != 2 && words.size() != 4) return fail("Kd needs 1 or 3 numbers");
            glm::vec3 c{0.0f};
            for (std::size_t i = 1; i < words.size(); ++i)
                if (!parseNumber(words[i], c[int(i - 1)]))
                    return fail(fmt::format("Kd value '{}' is not a finite number", words[i]));
            if (words.size() == 2) c = glm::vec3(c.x);
            m.diffuse = glm::clamp(c, glm::vec3(0.0f), glm::vec3(1.0f));
        } else if (key == "d" || key == "tr") {
            // "d -halo 0.5" is legal MTL: the halo flag is dropped.
            std::size_t i = 1;
            if (i < words.size() && lowercase(words[i]) == "-halo") ++i;
            float v = 0.0f;
            if (i + 1 != words.size() || !parseNumber(words[i], v))
                return fail(fmt::format("{} needs one finite number", words[0]));
            m.dissolve = std::clamp(key == "d" ? v : 1.0f - v, 0.0f, 1.0f);
        } else {  // map_kd
            std::size_t i = 1;
            while (i < words.size() && words[i].size() > 1 && words[i][0] == '-' &&
                   !isNumber(words[i])) {
                bool upToThree = false;
                const int n = optionArgs(lowercase(words[i]), upToThree);
                ++i;
                for (int k = 0; k < n && i < words.size(); ++k) {
                    if (upToThree && !isNumber(words[i])) break;
                    ++i;
                }
            }
            if (i >= words.size()) return fail("map_Kd without a file name");
            m.diffuseMap = joinFrom(words, i);
        }
    }
    return materials;
}

Result<std::vector<MtlMaterial>> loadMtl(const std::filesystem::path& path) {
    Result<std::string> text = readAll(path, "mvr::loadMtl()");
    if (!text) return text.status();
    return parseMtl(*text, path.string());
}

Result<std::vector<MtlMaterial>> loadObjMaterials(const std::filesystem::path& objPath) {
    Result<std::string> text = readAll(objPath, "mvr::loadObjMaterials()");
    if (!text) return text.status();
    std::vector<MtlMaterial> all;
    std::istringstream lines(*text);
    std::string line;
    while (std::getline(lines, line)) {
        if (const std::size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
        if (!line.empty() && line.back() == '\r') line.pop_back();
        const std::vector<std::string_view> words = splitWords(line);
        if (words.size() < 2 || lowercase(words[0]) != "mtllib") continue;
        // Every following word is a library (file names with spaces are not supported by OBJ).
        for (std::size_t i = 1; i < words.size(); ++i) {
            Result<std::vector<MtlMaterial>> lib =
                loadMtl(objPath.parent_path() / std::string(words[i]));
            if (!lib) return lib.status();
            all.insert(all.end(), lib->begin(), lib->end());
        }
    }
    return all;
}

const MtlMaterial* findMtl(const std::vector<MtlMaterial>& materials, std::string_view name) {
    for (const MtlMaterial& m : materials)
        if (m.name == name) return &m;
    return nullptr;
}

}  // namespace mvr

// tests/fuzz/standalone_main.cpp — the main() of a fuzz target when it is not built with
// libFuzzer (gcc, or MVR_BUILD_FUZZERS off): runs LLVMFuzzerTestOneInput once on every file
// named on the command line, or in a folder named there (sorted), and ignores libFuzzer-style
// "-flag=value" arguments. ctest runs each target over its seed corpus and its regression
// inputs this way in every build, so a crash found by fuzzing stays fixed in the Release and
// sanitizer builds too.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

int runFile(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        std::fprintf(stderr, "error: %s: cannot open for reading\n", path.c_str());
        return 1;
    }
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)),
                                  std::istreambuf_iterator<char>());
    std::vector<std::uint8_t> data(bytes.begin(), bytes.end());
    // A copy of exactly the file's size on the heap, as libFuzzer hands it over, so that
    // AddressSanitizer sees a read past its end.
    auto* exact = new std::uint8_t[std::max<std::size_t>(data.size(), 1)];
    std::copy(data.begin(), data.end(), exact);
    LLVMFuzzerTestOneInput(exact, data.size());
    delete[] exact;
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    int inputs = 0;
    int failures = 0;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg.rfind('-', 0) == 0) continue;
        std::error_code ec;
        if (std::filesystem::is_directory(arg, ec)) {
            std::vector<std::filesystem::path> files;
            for (const auto& entry : std::filesystem::directory_iterator(arg))
                if (entry.is_regular_file()) files.push_back(entry.path());
            std::sort(files.begin(), files.end());
            for (const auto& f : files) {
                failures += runFile(f);
                ++inputs;
            }
        } else {
            failures += runFile(arg);
            ++inputs;
        }
    }
    std::printf("%s: ran %d inputs\n", argc > 0 ? argv[0] : "fuzz", inputs);
    return failures ? 1 : 0;
}

// A fuzz target without libFuzzer: feeds every file of the given directories (and files) to the
// target's LLVMFuzzerTestOneInput once, in name order. tests/fuzz/CMakeLists.txt builds one
// replay executable per target in every test build, and ctest runs each over its checked-in
// corpus (tests/fuzz/corpus/<dir>): the seeds and every input a fuzzer run found a defect with
// stay regression inputs in CI, also under ASan+UBSan. A reader's crash, a sanitizer report or
// an exception other than aero::Error (which the targets catch) fails the run; the name of the
// input is printed before it runs, so the last line names the culprit.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <system_error>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

namespace fs = std::filesystem;

bool collect(const fs::path& p, std::vector<fs::path>& inputs) {
    std::error_code ec;
    if (fs::is_directory(p, ec)) {
        std::vector<fs::path> files;
        for (const auto& e : fs::directory_iterator(p, ec)) {
            if (e.is_regular_file()) files.push_back(e.path());
        }
        if (ec) return false;
        std::sort(files.begin(), files.end());
        inputs.insert(inputs.end(), files.begin(), files.end());
        return true;
    }
    if (fs::is_regular_file(p, ec)) {
        inputs.push_back(p);
        return true;
    }
    return false;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s DIR|FILE...  (runs the fuzz target once on every input)\n", argv[0]);
        return 2;
    }
    std::vector<fs::path> inputs;
    for (int a = 1; a < argc; ++a) {
        if (!collect(argv[a], inputs)) {
            std::fprintf(stderr, "%s: '%s' is neither a readable directory nor a file\n", argv[0], argv[a]);
            return 2;
        }
    }
    if (inputs.empty()) {
        std::fprintf(stderr, "%s: no inputs found\n", argv[0]);
        return 1;
    }
    std::size_t bytes = 0;
    for (const fs::path& p : inputs) {
        std::ifstream in(p, std::ios::binary);
        const std::vector<char> data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (!in.eof() && in.fail()) {
            std::fprintf(stderr, "%s: cannot read '%s'\n", argv[0], p.c_str());
            return 2;
        }
        std::printf("%s (%zu bytes)\n", p.c_str(), data.size());
        std::fflush(stdout);
        LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(data.data()), data.size());
        bytes += data.size();
    }
    std::printf("replayed %zu inputs, %zu bytes\n", inputs.size(), bytes);
    return 0;
}

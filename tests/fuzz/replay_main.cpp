// Runs a fuzzing target over files, without libFuzzer: `fuzz_replay_X FILE|DIR...` feeds each
// file (each file of each directory, recursively, in name order) to LLVMFuzzerTestOneInput.
// Built with any compiler, in every build, so the inputs that once crashed odec
// (tests/fuzz/regressions/) are replayed by CTest even where there is no clang.
// `--print` first: print what each input is for a person (for the interpreter, the script,
// generated or not) and run nothing; the target reads ODEC_FUZZ_PRINT.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

int main(int argc, char** argv) {
    namespace fs = std::filesystem;
    std::vector<std::string> files;
    bool print = false;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--print") == 0) {
            print = true;
            setenv("ODEC_FUZZ_PRINT", "only", 1);
            continue;
        }
        // Absolute, since a target may change the working directory.
        const fs::path p = fs::absolute(argv[i]);
        if (fs::is_directory(p)) {
            for (const auto& e : fs::recursive_directory_iterator(p)) {
                if (e.is_regular_file()) files.push_back(e.path().string());
            }
        } else {
            files.push_back(p.string());
        }
    }
    std::sort(files.begin(), files.end());
    if (files.empty()) {
        std::fprintf(stderr, "usage: %s FILE|DIR...  (no input files found)\n", argv[0]);
        return 2;
    }
    for (const std::string& f : files) {
        std::ifstream in(f, std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (print) {
            if (files.size() > 1) std::printf("; ---- %s\n", f.c_str());
        } else {
            std::printf("replaying %s (%zu bytes)\n", f.c_str(), bytes.size());
        }
        std::fflush(stdout);
        LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    }
    if (!print) std::printf("%zu inputs replayed, none crashed\n", files.size());
    return 0;
}

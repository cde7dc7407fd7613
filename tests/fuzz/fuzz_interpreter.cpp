// Fuzzing target: the bytes are a script, run by the real interpreter with the real engine
// and command table (pictures are built as scenes and not drawn: odec_no_pictures). Each
// line (with its continuation lines) runs as a command typed at the prompt: an error is
// reported and the next line runs, so one bad line does not hide the rest. Nothing may
// crash, trip a sanitizer or leave the model's arrays inconsistent; the session's bounds
// (fuzz_common.h) keep any input under a second.
//
// An input whose first byte is kGeneratorMarker (0x01) is not text: the rest of its bytes are
// the choices of the script generator (script_gen.h), and the script it makes runs instead,
// after the files it calls are written into the scratch directory.
//
// ODEC_FUZZ_PRINT=1 in the environment prints each script (generated or not) on stdout
// before it runs, then what the session prints (its output and errors) as it runs;
// ODEC_FUZZ_PRINT=only prints the script and runs nothing (`fuzz_replay_interpreter --print
// FILE` sets it so).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <string>

#include "commands.h"
#include "fuzz_common.h"
#include "script_gen.h"

namespace {

bool consistent(const odec::Model& m) {
    const auto& b = m.blocks;
    const size_t n = b.id.size();
    const auto& c = m.contacts;
    const size_t nc = c.block_a.size();
    bool ok = b.shape.size() == n && b.centroid.size() == n && b.orientation.size() == n && b.vel.size() == n &&
              b.mass.size() == n && b.flags.size() == n && b.group.size() == n && b.half_kick.size() == n &&
              b.material.size() == n && b.volume.size() == n;
    ok = ok && c.block_b.size() == nc && c.id.size() == nc;
    for (size_t k = 0; ok && k < nc; ++k) {
        ok = c.block_a[k] >= 0 && c.block_b[k] >= 0 && static_cast<size_t>(c.block_a[k]) < n &&
             static_cast<size_t>(c.block_b[k]) < n;
    }
    return ok;
}

// A line ends a command unless it ends in a continuation mark ('&' or '...').
bool continues(const std::string& line) {
    size_t end = line.find(';');
    if (end == std::string::npos) end = line.size();
    while (end > 0 && (line[end - 1] == ' ' || line[end - 1] == '\t' || line[end - 1] == '\r')) --end;
    return (end >= 1 && line[end - 1] == '&') || (end >= 3 && line.compare(end - 3, 3, "...") == 0);
}

// ODEC_FUZZ_PRINT: 0 nothing, 1 print and run, 2 print only.
int print_mode() {
    static const int mode = [] {
        const char* e = std::getenv("ODEC_FUZZ_PRINT");
        if (!e || !*e || std::strcmp(e, "0") == 0) return 0;
        return std::strcmp(e, "only") == 0 ? 2 : 1;
    }();
    return mode;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > 65536) return -1; // a script, not a data file: keep each input quick
    odec::fuzz::fresh_scratch_dir();
    std::string text;
    if (size > 0 && data[0] == odec::fuzz::kGeneratorMarker) {
        const odec::fuzz::GeneratedScript g = odec::fuzz::generate_script(data + 1, size - 1, odec::command_table());
        for (const auto& f : g.files) {
            std::ofstream file(f.first, std::ios::binary | std::ios::trunc);
            file << f.second;
        }
        text = g.text;
        if (print_mode()) {
            std::fputs(odec::fuzz::printable(g).c_str(), stdout);
            std::fflush(stdout);
        }
    } else {
        text.assign(reinterpret_cast<const char*>(data), size);
        if (print_mode()) {
            std::fwrite(text.data(), 1, text.size(), stdout);
            if (!text.empty() && text.back() != '\n') std::fputc('\n', stdout);
            std::fflush(stdout);
        }
    }
    if (print_mode() == 2) return 0;
    odec::fuzz::NullBuffer sink;
    std::streambuf* to = print_mode() == 1 ? std::cout.rdbuf() : &sink;
    std::ostream out(to), err(to);
    odec::Model model;
    odec::Interpreter interp(model, odec::command_table(), out, err);
    odec::fuzz::bound_session(interp);
    size_t at = 0;
    std::string chunk;
    while (at < text.size() && !interp.quit_requested) {
        size_t nl = text.find('\n', at);
        if (nl == std::string::npos) nl = text.size();
        const std::string line = text.substr(at, nl - at);
        at = nl + 1;
        chunk += line;
        chunk += '\n';
        // A FISH definition is one piece, up to its 'end'.
        if ((continues(line) || odec::definition_open(chunk)) && at < text.size()) continue;
        interp.run_text("fuzz.dat", chunk, true);
        chunk.clear();
        if (!consistent(model)) {
            std::fprintf(stderr, "odec fuzz: the model's arrays are inconsistent\n");
            std::abort();
        }
    }
    return 0;
}

// Fuzzing target: the bytes are a script, run by the real interpreter with the real engine
// and command table (pictures are built as scenes and not drawn: odec_no_pictures). Each
// line (with its continuation lines) runs as a command typed at the prompt: an error is
// reported and the next line runs, so one bad line does not hide the rest. Nothing may
// crash, trip a sanitizer or leave the model's arrays inconsistent; the session's bounds
// (fuzz_common.h) keep any input under a second.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <string>

#include "commands.h"
#include "fuzz_common.h"

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

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > 65536) return -1; // a script, not a data file: keep each input quick
    odec::fuzz::fresh_scratch_dir();
    odec::fuzz::NullBuffer sink;
    std::ostream out(&sink), err(&sink);
    odec::Model model;
    odec::Interpreter interp(model, odec::command_table(), out, err);
    odec::fuzz::bound_session(interp);
    const std::string text(reinterpret_cast<const char*>(data), size);
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

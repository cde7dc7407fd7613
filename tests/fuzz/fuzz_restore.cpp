// Fuzzing target: the bytes are a save file, given to restore_model. A file that is refused
// (truncated, flipped, foreign, empty, newer) must leave the model as it was; a file that is
// taken must give a model that saves, restores into a fresh model and saves again to the same
// bytes, and that prints, cycles, plots (scenes only), saves and restores again without
// crashing. Each input is tried twice: as it is, and, when it begins like a save
// file, with its payload length and checksum made right, so that mutations reach the
// sections behind the checksum.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

#include "commands.h"
#include "fuzz_common.h"
#include "io/save.h"

namespace {

// The model every input is restored over: a few blocks in contact, with histories and a table.
const odec::Model& base_model() {
    static const odec::Model model = [] {
        odec::Model m;
        odec::fuzz::NullBuffer sink;
        std::ostream out(&sink);
        odec::Interpreter interp(m, odec::command_table(), out, out);
        interp.quiet = true;
        if (!interp.run_text("base.dat",
                             "poly brick 0 2 0 2 0 1\npoly brick 0.2 1.8 0.2 1.8 1 2\njset dip 90 dd 90 origin 1,1,1\n"
                             "prop mat=1 dens=2000\nprop jmat=1 jkn=1e8 jks=1e8 jfric=30\ngrav 0 0 -10\n"
                             "fix range z 0 0.5\nhist zdis 1,1,1.5\ntable 1 0,0 1,1\nstep 20\n",
                             false)) {
            std::abort();
        }
        return m;
    }();
    return model;
}

bool same(const odec::Model& a, const odec::Model& b) {
    return a.blocks.size() == b.blocks.size() && a.blocks.id == b.blocks.id && a.contacts.size() == b.contacts.size() &&
           a.step == b.step && a.time == b.time && a.title == b.title && a.blocks.centroid == b.blocks.centroid &&
           a.histories.items.size() == b.histories.items.size() && a.joint_planes.size() == b.joint_planes.size();
}

void try_file(const std::string& bytes) {
    odec::fuzz::fresh_scratch_dir();
    {
        std::ofstream f("in.sav", std::ios::binary | std::ios::trunc);
        f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    }
    odec::Model model = base_model();
    std::string error;
    if (!odec::restore_model("in.sav", model, error)) {
        if (error.empty() || !same(model, base_model())) {
            std::fprintf(stderr, "odec fuzz: a refused restore changed the model or gave no reason\n");
            std::abort();
        }
        return;
    }
    // Taken: save and restore share one validation, so the model saves, and it round-trips:
    // restored into a fresh model and saved again, it gives the same bytes.
    if (!odec::check_save_round_trip(model, ".", error)) {
        std::fprintf(stderr, "odec fuzz: a restored model does not round-trip: %s\n", error.c_str());
        std::abort();
    }
    // And it is usable.
    odec::fuzz::NullBuffer sink;
    std::ostream out(&sink);
    odec::Interpreter interp(model, odec::command_table(), out, out);
    odec::fuzz::bound_session(interp);
    const char* lines[] = {"print info", "print block", "print contact", "print max", "print hist 1",
                           "print prop", "print table 1", "plot block disp vector vel", "plot contact state",
                           "plot principal", "plot hist 1", "export vtk 'e'", "step 5", "solve cycles 5",
                           "save 'again'", "restore 'again'", "step 2", "delete range id 1", "step 2"};
    for (const char* line : lines) interp.run_text("after-restore.dat", line, true);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > (1u << 20)) return -1;
    const std::string bytes(reinterpret_cast<const char*>(data), size);
    try_file(bytes);
    // The same bytes with a header and checksum that agree with them.
    const size_t magic = 12, checksum = 8;
    if (size < magic + 4 + 8 || std::memcmp(data, "ODEC-SAVE\r\n\x1a", magic) != 0) return 0;
    std::uint64_t n;
    std::memcpy(&n, data + magic + 4, 8);
    if (n > 256) return 0;
    const size_t header = magic + 4 + 8 + static_cast<size_t>(n) + 8;
    if (size < header + checksum) return 0;
    std::string fixed = bytes;
    const std::uint64_t payload = size - header - checksum;
    std::memcpy(&fixed[header - 8], &payload, 8);
    std::uint64_t h = 0xcbf29ce484222325ull; // FNV-1a 64, as save.cpp
    for (size_t i = 0; i + checksum < size; ++i) {
        h ^= static_cast<unsigned char>(fixed[i]);
        h *= 0x100000001b3ull;
    }
    std::memcpy(&fixed[size - checksum], &h, 8);
    if (fixed != bytes) try_file(fixed);
    return 0;
}

// Nothing a user types may crash odec: thousands of random commands, made of real command
// words, keywords and awkward values, run through the interpreter. Each either works or is
// refused with a located error; the model's arrays stay consistent throughout.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "test_util.h"

using odec::test::Session;

namespace {

// Small deterministic generator (the same sequence on every machine).
struct Rng {
    std::uint64_t s;
    std::uint64_t next() {
        s += 0x9e3779b97f4a7c15ull;
        std::uint64_t z = s;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }
    size_t pick(size_t n) { return static_cast<size_t>(next() % n); }
};

const char* kValues[] = {"0", "1", "-1", "2.5", "-3", "10", "1e9", "-1e9", "1e300", "-1e-300", "0.001", "7",
                         "90", "45", "'name'", "abc", "(", ")", "(1,2,3)", "1,2,3", "&", "=", "'unterminated",
                         "x", "z", "region", "range", "not", "id", "group", "plane", "dip", "dd", "origin"};

bool consistent(const odec::Model& m) {
    const auto& b = m.blocks;
    const size_t n = b.id.size();
    return b.shape.size() == n && b.centroid.size() == n && b.vel.size() == n && b.mass.size() == n &&
           b.flags.size() == n && b.group.size() == n && b.half_kick.size() == n;
}

} // namespace

TEST(Monkey, RandomCommandsNeverCrashTheInterpreter) {
    Session s;
    Rng rng{12345};
    // Command words people type, minus those that touch files or cycle without end.
    std::vector<std::string> verbs;
    for (const odec::CommandSpec* c : odec::command_table().commands) {
        const std::string& n = c->name;
        if (n == "call" || n == "save" || n == "restore" || n == "plot" || n == "export" || n == "quit" ||
            n == "step" || n == "solve" || n == "history" || n == "table") {
            continue;
        }
        verbs.push_back(n);
    }
    // A model to work on.
    ASSERT_TRUE(s.run("poly brick 0 2 0 2 0 2\njset dip 30 dd 60 origin 1,1,1\nprop mat=1 dens=2000\n"
                      "prop jmat=1 jkn=1e8 jks=1e8 jfric=30\ngrav 0 0 -10\nfix range z 0 0.5"));
    int ok = 0, refused = 0;
    for (int k = 0; k < 4000; ++k) {
        const odec::CommandSpec* spec = odec::command_table().find(verbs[rng.pick(verbs.size())]);
        std::string line = spec->name;
        const int n_words = static_cast<int>(rng.pick(9));
        for (int w = 0; w < n_words; ++w) {
            line += " ";
            if (!spec->keywords.empty() && rng.pick(2) == 0) {
                line += spec->keywords[rng.pick(spec->keywords.size())].name;
            } else {
                line += kValues[rng.pick(sizeof kValues / sizeof *kValues)];
            }
        }
        s.err.str("");
        // Now and then let the model move, so that commands meet contacts and motion.
        if (k % 200 == 199) s.run("step 5");
        (s.run(line) ? ok : refused)++;
        ASSERT_TRUE(consistent(s.model)) << "after: " << line;
        if (s.model.blocks.size() > 2000) s.run("new"); // keep cutting from growing without bound
    }
    std::printf("[monkey] %d commands worked, %d were refused with an error\n", ok, refused);
    EXPECT_GT(ok, 100);
    EXPECT_GT(refused, 100);
}

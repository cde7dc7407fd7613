// Real public 3DEC/UDEC scripts (../shared/corpus beside the checkout): odec must read what it
// can of them. Every file must lex; the commands of the classic 3DEC geometry and property
// language must parse. FISH (def ... end) comes later and is skipped here.
#include <gtest/gtest.h>

#include <cstdio>
#include <dirent.h>
#include <map>

#include "commands.h"
#include "lang/interpreter.h"

namespace {

const std::string kCorpus = std::string(ODEC_SOURCE_DIR) + "/../shared/corpus/";

struct Count {
    int commands = 0, parsed = 0, fish = 0;
    std::map<std::string, int> failures; // first words of the message
};

Count read_corpus_file(const std::string& path) {
    Count n;
    bool ok = false;
    const std::string text = odec::read_file_text(path, ok);
    EXPECT_TRUE(ok) << path;
    auto f = std::make_shared<odec::SourceFile>();
    f->name = path;
    f->lines = odec::split_lines(text);
    odec::Lexer lexer(f);
    odec::LexedCommand c;
    bool in_def = false, in_command = false;
    odec::NamedRanges named; // `range name X ...` as the interpreter would keep them
    try {
        while (lexer.next(c)) {
            const std::string& verb = c.tokens[0].lower;
            if (verb == "def" || verb == "define") {
                in_def = true;
                continue;
            }
            if (in_def) {
                if (verb == "command") {
                    in_command = true;
                    continue;
                }
                if (verb == "endcommand") {
                    in_command = false;
                    continue;
                }
                if (verb == "end") in_def = false;
                if (!in_command) {
                    ++n.fish;
                    continue;
                }
            }
            ++n.commands;
            try {
                const odec::Args a = odec::parse_command(odec::command_table(), c.tokens, &named);
                if (a.command->name == "range" && a.has("name")) {
                    std::string key = a.text("name");
                    for (char& ch : key) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
                    named[key] = a.range;
                }
                ++n.parsed;
            } catch (const odec::CommandError& e) {
                ++n.failures[e.diag.what.substr(0, 60)];
            }
        }
    } catch (const odec::CommandError& e) {
        ADD_FAILURE() << "lexical error: " << odec::format_diagnostic(e.diag);
    }
    return n;
}

std::vector<std::string> corpus_files() {
    std::vector<std::string> out;
    for (const char* sub : {"3dec/", "udec/"}) {
        DIR* d = opendir((kCorpus + sub).c_str());
        if (!d) continue;
        while (dirent* e = readdir(d)) {
            const std::string name = e->d_name;
            if (name.size() > 4 && name.substr(name.size() - 4) == ".dat") out.push_back(kCorpus + sub + name);
        }
        closedir(d);
    }
    std::sort(out.begin(), out.end());
    return out;
}

} // namespace

TEST(Corpus, EveryFileLexesAndTheClassicCommandsParse) {
    const auto files = corpus_files();
    if (files.empty()) GTEST_SKIP() << "no corpus beside the checkout";
    int total = 0, parsed = 0;
    for (const auto& path : files) {
        const Count n = read_corpus_file(path);
        total += n.commands;
        parsed += n.parsed;
        std::printf("[corpus] %-70s %4d of %4d commands parse (%d FISH lines skipped)\n",
                    path.substr(kCorpus.size()).c_str(), n.parsed, n.commands, n.fish);
        for (const auto& [what, k] : n.failures) std::printf("[corpus]     %3d x %s\n", k, what.c_str());
    }
    std::printf("[corpus] all: %d of %d commands parse\n", parsed, total);
    // A floor, not a goal: what parses today must keep parsing (most of the rest is FISH).
    EXPECT_GE(parsed, 631);
    const Count grav = read_corpus_file(kCorpus + "3dec/demifang_grav.dat");
    EXPECT_EQ(grav.parsed, grav.commands);
}

TEST(Corpus, TempleGeometryParsesWhole) {
    // 156 prism blocks with continuation glued to ')' and named ranges.
    const std::string path = kCorpus + "3dec/anayeri_m03_geometry.dat";
    if (corpus_files().empty()) GTEST_SKIP() << "no corpus beside the checkout";
    const Count n = read_corpus_file(path);
    int prisms_failed = 0;
    for (const auto& [what, k] : n.failures) {
        if (what.find("prism") != std::string::npos) prisms_failed += k;
    }
    EXPECT_EQ(prisms_failed, 0);
}

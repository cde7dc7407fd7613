#include <gtest/gtest.h>

#include "lang/lexer.h"

using namespace odec;

namespace {

std::vector<LexedCommand> lex_all(const std::string& text) {
    auto f = std::make_shared<SourceFile>();
    f->name = "t.dat";
    f->lines = split_lines(text);
    Lexer lx(f);
    std::vector<LexedCommand> out;
    LexedCommand c;
    while (lx.next(c)) out.push_back(c);
    return out;
}

std::vector<std::string> texts(const LexedCommand& c) {
    std::vector<std::string> out;
    for (const Token& t : c.tokens) out.push_back(t.text);
    return out;
}

} // namespace

TEST(Lexer, SeparatorsAreBlanksCommasAndEquals) {
    const auto a = lex_all("prop mat=1 dens=2000");
    const auto b = lex_all("prop mat 1 dens 2000");
    const auto c = lex_all("prop mat,1,dens,2000");
    ASSERT_EQ(a.size(), 1u);
    EXPECT_EQ(texts(a[0]), texts(b[0]));
    EXPECT_EQ(texts(a[0]), texts(c[0]));
    EXPECT_EQ(texts(a[0]), (std::vector<std::string>{"prop", "mat", "1", "dens", "2000"}));
}

TEST(Lexer, CaseIsFoldedForMatchingButKeptForText) {
    const auto a = lex_all("PROP Mat=1");
    EXPECT_EQ(a[0].tokens[0].lower, "prop");
    EXPECT_EQ(a[0].tokens[0].text, "PROP");
}

TEST(Lexer, NumbersInEveryUsualForm) {
    const char* forms[] = {"1", "1.5", "-2e9", "1.5E+07", ".5", "2.", "+3", "2.900000e+001", "-0.0"};
    const double values[] = {1, 1.5, -2e9, 1.5e7, 0.5, 2.0, 3.0, 29.0, -0.0};
    for (size_t i = 0; i < sizeof forms / sizeof *forms; ++i) {
        double v = 0;
        EXPECT_TRUE(parse_number(forms[i], v)) << forms[i];
        EXPECT_EQ(v, values[i]) << forms[i];
    }
    double v;
    for (const char* bad : {"e5", "1e", "1.2.3", "-", ".", "1x", "x1", "--1"}) EXPECT_FALSE(parse_number(bad, v)) << bad;
}

TEST(Lexer, CommentsEndTheLine) {
    const auto a = lex_all("grav 0 0 -10 ; gravity\n; a whole comment line\n\nstep 10");
    ASSERT_EQ(a.size(), 2u);
    EXPECT_EQ(texts(a[0]).size(), 4u);
    EXPECT_EQ(a[1].first_line, 4);
}

TEST(Lexer, AmpersandAndDotsContinue) {
    const auto a = lex_all("poly brick 0 1 &\n  0 1 ...\n  0 1\nstep 1");
    ASSERT_EQ(a.size(), 2u);
    EXPECT_EQ(texts(a[0]), (std::vector<std::string>{"poly", "brick", "0", "1", "0", "1", "0", "1"}));
    EXPECT_EQ(a[0].first_line, 1);
    EXPECT_EQ(a[0].last_line, 3);
    EXPECT_EQ(a[0].tokens[4].loc.line, 2); // each token keeps its own line
    EXPECT_EQ(a[1].first_line, 4);
}

TEST(Lexer, AmpersandGluedToAParenthesisOrNumber) {
    const auto a = lex_all("a (0,0,1)&\n(1,1,1) 2.0&\n3");
    ASSERT_EQ(a.size(), 1u);
    EXPECT_EQ(texts(a[0]), (std::vector<std::string>{"a", "(", "0", "0", "1", ")", "(", "1", "1", "1", ")", "2.0", "3"}));
    EXPECT_EQ(a[0].tokens[11].kind, TokenKind::Number);
}

TEST(Lexer, ContinuationIntoABlankLineEndsTheCommand) {
    const auto a = lex_all("poly brick 0 1 0 1 0 1 &\r\n   \r\nstep 1\r\n");
    ASSERT_EQ(a.size(), 2u);
    EXPECT_EQ(a[1].tokens[0].text, "step");
}

TEST(Lexer, VectorsInThreeForms) {
    for (const char* s : {"v 1,2,3", "v 1 2 3", "v (1,2,3)", "v (1 2 3)"}) {
        const auto a = lex_all(s);
        std::vector<double> nums;
        for (const Token& t : a[0].tokens) {
            if (t.kind == TokenKind::Number) nums.push_back(t.number);
        }
        EXPECT_EQ(nums, (std::vector<double>{1, 2, 3})) << s;
    }
}

TEST(Lexer, QuotedStringsKeepBlanksAndSemicolons) {
    const auto a = lex_all("title 'A slope; stage 1' \"x y\"");
    ASSERT_EQ(a[0].tokens.size(), 3u);
    EXPECT_EQ(a[0].tokens[1].kind, TokenKind::String);
    EXPECT_EQ(a[0].tokens[1].text, "A slope; stage 1");
    EXPECT_EQ(a[0].tokens[2].text, "x y");
    EXPECT_EQ(a[0].tokens[2].loc.col, 26);
}

TEST(Lexer, ColumnsAreOneBased) {
    const auto a = lex_all("  prop   dens=5");
    EXPECT_EQ(a[0].tokens[0].loc.col, 3);
    EXPECT_EQ(a[0].tokens[1].loc.col, 10);
    EXPECT_EQ(a[0].tokens[2].loc.col, 15);
}

TEST(Lexer, UnterminatedStringIsAnErrorWithItsPlace) {
    try {
        lex_all("title 'no end");
        FAIL() << "expected an error";
    } catch (const CommandError& e) {
        EXPECT_EQ(format_diagnostic(e.diag),
                  "t.dat:1:7: error: unterminated string: no closing ' on this line\n"
                  "    title 'no end\n"
                  "          ^~~~~~~\n"
                  "  expected the string to end with ' before the end of the line\n");
    }
}

// The README tells the truth: its first script is the file it names, and that file runs.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

namespace {
std::string slurp(const std::string& path) {
    std::ifstream f(path);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}
} // namespace

TEST(Readme, FirstScriptIsTheFileItNames) {
    const std::string readme = slurp(std::string(ODEC_SOURCE_DIR) + "/README.md");
    const size_t section = readme.find("## A first script");
    ASSERT_NE(section, std::string::npos);
    const size_t open = readme.find("```\n", section);
    const size_t close = readme.find("```\n", open + 4);
    ASSERT_NE(close, std::string::npos);
    const std::string shown = readme.substr(open + 4, close - open - 4);
    EXPECT_EQ(shown, slurp(std::string(ODEC_SOURCE_DIR) + "/examples/tutorial/free-fall.dat"));
}

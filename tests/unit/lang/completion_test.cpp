#include <gtest/gtest.h>

#include "commands.h"
#include "lang/completion.h"

using odec::complete_words;

TEST(Completion, CommandsAtTheStart) {
    const auto w = complete_words(odec::command_table(), "", "pr");
    EXPECT_EQ(w, (std::vector<std::string>{"property", "print"}));
}

TEST(Completion, KeywordsOfTheCommand) {
    const auto w = complete_words(odec::command_table(), "prop mat=1 ", "jk");
    EXPECT_EQ(w, (std::vector<std::string>{"jkn", "jks"}));
}

TEST(Completion, RangeFiltersAfterRange) {
    const auto w = complete_words(odec::command_table(), "fix range ", "re");
    EXPECT_EQ(w, (std::vector<std::string>{"region"}));
}

TEST(Completion, ChoiceWords) {
    const auto w = complete_words(odec::command_table(), "set echo ", "");
    EXPECT_EQ(w, (std::vector<std::string>{"on", "off"}));
}

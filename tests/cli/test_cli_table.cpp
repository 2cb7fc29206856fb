// The command table itself (gdof_cli_lib): every row complete, names unique,
// help sections in one piece, and the order facts the parser relies on.
#include <gtest/gtest.h>

#include <set>

#include "cli.h"

using gdof::cli::Command;
using gdof::cli::command_table;
using gdof::cli::Kind;

TEST(cli_table, EveryRowHasNamesHelpGroupAndTheRunnerOfItsKind) {
    ASSERT_GT(command_table().size(), 50u);
    for (const Command& c : command_table()) {
        ASSERT_FALSE(c.names.empty());
        const std::string& n = c.names.front();
        for (const std::string& name : c.names) EXPECT_EQ(name.rfind('-', 0), 0u) << name;
        EXPECT_FALSE(c.help.empty()) << n;
        EXPECT_FALSE(c.group.empty()) << n;
        EXPECT_EQ(bool(c.print), c.kind == Kind::Immediate) << n;
        EXPECT_EQ(bool(c.set), c.kind == Kind::Global) << n;
        EXPECT_EQ(bool(c.run), c.kind == Kind::Modifier || c.kind == Kind::Action) << n;
        for (int k : c.file_args) EXPECT_TRUE(k >= 0 && k < c.nargs()) << n << " file argument " << k;
        if (c.optional_value) {
            EXPECT_EQ(c.nargs(), 0) << n << ": --flag=VALUE is its only argument";
        }
        if (c.kind == Kind::Immediate || c.kind == Kind::Global) {
            EXPECT_FALSE(c.check || c.preflight || c.lets_wait) << n << ": acted on while parsing";
            EXPECT_EQ(c.stack, gdof::cli::StackUse::None) << n;
        }
    }
}

TEST(cli_table, NamesAreUniqueAndFindCommandFindsEach) {
    std::set<std::string> seen;
    for (const Command& c : command_table())
        for (const std::string& name : c.names) {
            EXPECT_TRUE(seen.insert(name).second) << name << " is in two rows";
            EXPECT_EQ(gdof::cli::find_command(name), &c) << name;
        }
    EXPECT_EQ(gdof::cli::find_command("--frobnicate"), nullptr);
    EXPECT_EQ(gdof::cli::input_command().names.front(), "-i");
}

TEST(cli_table, EachHelpSectionIsOnePieceOfTheTable) {
    std::set<std::string> done;
    std::string group;
    for (const Command& c : command_table()) {
        if (c.group == group) continue;
        EXPECT_TRUE(done.insert(group).second) << "section '" << c.group << "' is split by '" << group << "'";
        group = c.group;
    }
}

TEST(cli_table, ArgumentCountFollowsTheMetavariables) {
    EXPECT_EQ(gdof::cli::find_command("--info")->nargs(), 0);
    EXPECT_EQ(gdof::cli::find_command("-o")->nargs(), 1);
    EXPECT_EQ(gdof::cli::find_command("--colorconvert")->nargs(), 2);
    EXPECT_EQ(gdof::cli::find_command("--layers")->nargs(), 1);  // "N|auto[:OPTS]|id[:CHANNEL]"
}

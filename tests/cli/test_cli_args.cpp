// The CLI's parsing helpers in process (gdof_cli_lib): strict numbers, argv
// -> Program, frame numbers in file arguments, library errors naming flags,
// flag-named text files.
#include "cli.h"
#include "cli/cli_test_helpers.h"

using namespace gdof::cli;
using gdof::test::contains;
using gdof::test::ScratchDir;

namespace {

// The CliError a call throws (code -1 and "" if none).
template <class F>
CliError error_of(F&& f) {
    try {
        f();
    } catch (const CliError& e) {
        return e;
    }
    return CliError(-1, "");
}

Program parse(const std::vector<std::string>& argv) {
    int code = -1;
    std::optional<Program> p = parse_args(argv, code);
    EXPECT_TRUE(p.has_value());
    return p ? *p : Program{};
}

CliError parse_error(const std::vector<std::string>& argv) {
    return error_of([&] {
        int code = -1;
        (void)parse_args(argv, code);
    });
}

}  // namespace

TEST(cli_values, IntegersAreParsedAsIntegers) {
    EXPECT_EQ(to_integer("12"), 12);
    EXPECT_EQ(to_integer("-3"), -3);
    EXPECT_FALSE(to_integer("2.5"));
    EXPECT_FALSE(to_integer("1e3"));
    EXPECT_FALSE(to_integer(""));
    EXPECT_FALSE(to_integer("7x"));
    EXPECT_EQ(parse_int("--soft", "4"), 4);
    CliError e = error_of([] { parse_int("--soft", "2.5"); });
    EXPECT_EQ(e.code, kUsageError);
    EXPECT_STREQ(e.what(), "--soft: expected an integer, got '2.5'");
    EXPECT_EQ(error_of([] { parse_int("--soft", "2000000"); }).code, kUsageError);
    EXPECT_EQ(parse_count("--spp", "8", 1), 8);
    e = error_of([] { parse_count("--spp", "8.0", 1); });
    EXPECT_EQ(e.code, kUsageError);
    EXPECT_STREQ(e.what(), "--spp: expected an integer >= 1, got '8.0'");
    EXPECT_EQ(error_of([] { parse_count("--spp", "0", 1); }).code, kUsageError);
    EXPECT_DOUBLE_EQ(parse_double("--depth-scale", "2.5e-1"), 0.25);
    EXPECT_STREQ(error_of([] { parse_double("--depth-scale", "abc"); }).what(),
                 "--depth-scale: expected a number, got 'abc'");
}

TEST(cli_args, IntegerFlagsRejectFractionsWhileParsing) {
    for (const char* flag : {"--soft", "--adi-steps", "--threads"}) {
        const CliError e = parse_error({flag, "2.5", "in.exr", "-o", "out.exr"});
        EXPECT_EQ(e.code, kUsageError) << flag;
        EXPECT_TRUE(contains(e.what(), flag)) << e.what();
        EXPECT_TRUE(contains(e.what(), "'2.5'")) << e.what();
    }
}

TEST(cli_args, StepsKeepTheirRowsAndInputsBecomeInputs) {
    const Program p = parse({"--threads=3", "-i", "a.exr", "b.exr", "--soft", "2", "--composite", "m.json",
                             "--aovs", "-o", "out.exr"});
    EXPECT_EQ(p.global.threads, 3);
    ASSERT_EQ(p.steps.size(), 6u);
    EXPECT_TRUE(p.steps[0].is_input());
    EXPECT_EQ(p.steps[0].args, std::vector<std::string>{"a.exr"});
    EXPECT_TRUE(p.steps[1].is_input());
    EXPECT_EQ(p.steps[2].name(), "--soft");
    EXPECT_EQ(p.steps[2].def, find_command("--soft"));
    EXPECT_EQ(p.steps[4].args.size(), 0u);
    EXPECT_FALSE(p.steps[5].stack_output);
    EXPECT_EQ(parse({"--aovs=all", "--composite", "m.json", "-o", "x.exr"}).steps[0].args,
              std::vector<std::string>{"all"});
}

TEST(cli_args, StackOutputsAreMarked) {
    const Program p = parse({"--render", "s.json", "--stack", "st.json", "-o", "st/ref.####.exr", "in.exr", "-o",
                             "out.####.exr"});
    ASSERT_EQ(p.steps.size(), 5u);
    EXPECT_TRUE(p.steps[2].stack_output);
    EXPECT_FALSE(p.steps[4].stack_output);
}

TEST(cli_args, OrderRulesAreUsageErrors) {
    EXPECT_STREQ(parse_error({"-o", "x.exr"}).what(), "-o: no image on the stack (give an input file before -o)");
    EXPECT_STREQ(parse_error({"in.exr", "--diffuse", "--solver", "adi", "-o", "x.exr"}).what(),
                 "--solver: no --diffuse follows it (modifiers apply to the commands after them)");
    EXPECT_STREQ(parse_error({"--ch", "R"}).what(), "nothing to do: give an input file or a command");
    EXPECT_EQ(parse_error({"--render", "s.json", "--deep", "-o", "x.exr"}).code, -1) << "--deep after --render is fine";
}

TEST(cli_run, FrameNumbersGoIntoFileArgumentsOnly) {
    Step s;
    s.def = find_command("--colorconvert");
    s.args = {"lin.####", "b.####"};
    EXPECT_EQ(with_frame_number(s, *s.def, 7).args, s.args) << "--colorconvert takes no files";
    Step o;
    o.def = find_command("-o");
    o.args = {"out.####.exr"};
    EXPECT_EQ(with_frame_number(o, *o.def, 7).args, std::vector<std::string>{"out.0007.exr"});
    EXPECT_EQ(with_frame_number(o, *o.def, std::nullopt).args, o.args) << "no sequence";
    o.stack_output = true;
    EXPECT_EQ(with_frame_number(o, *o.def, 7).args, o.args) << "a stack's pattern numbers its references";
    Step in;
    in.args = {"in.%03d.exr"};
    EXPECT_EQ(with_frame_number(in, input_command(), 12).args, std::vector<std::string>{"in.012.exr"});
}

TEST(cli_errors, LibraryErrorsNameTheFlagOfTheirSetting) {
    using gdof::Status;
    using gdof::StatusCode;
    EXPECT_EQ(message_naming_flag(Status::error("no focal length", StatusCode::NotFound, "focal_length_mm")),
              "no focal length (--focal-length-mm)");
    EXPECT_EQ(message_naming_flag(Status::error("bad key", StatusCode::InvalidArgument, "no_such_setting")), "bad key");
    EXPECT_EQ(message_naming_flag(Status::error("plain")), "plain");
}

TEST(cli_errors, FlagFilesNameTheFlagAndTheFile) {
    ScratchDir dir;
    gdof::test::write_text(dir.file("a.json"), "{}");
    EXPECT_EQ(read_flag_file("--blurfield", "file", dir.file("a.json")), "{}");
    CliError e = error_of([&] { read_flag_file("--blurfield", "file", dir.file("none.json")); });
    EXPECT_EQ(e.code, kRuntimeError);
    EXPECT_EQ(std::string(e.what()), "--blurfield: file '" + dir.file("none.json") + "' not found");
    e = error_of([&] { read_flag_file("--surfaces", "file", dir.path().string()); });
    EXPECT_EQ(e.code, kRuntimeError);
    EXPECT_TRUE(contains(e.what(), "--surfaces: '" + dir.path().string() + "' is a folder")) << e.what();
}

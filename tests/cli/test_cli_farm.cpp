// gdof CLI driven by a render farm (docs/farm.md, "The gdof command line on
// a farm"): progress as whole lines when stderr is not a terminal, never
// going back within a frame and at most one a second; usage errors for a
// command line that writes nothing and for several frames written to one
// name; output folders checked before any work; OPERATION --help; help
// wrapped to 80 columns.
#include <chrono>
#include <regex>
#include <sstream>

#include "cli/cli_test_helpers.h"

using namespace gdof::test;

namespace {

struct ProgressLine {
    int frame = -1, index = -1, count = -1;  // -1: no frame field
    std::string stage;
    int percent = -1;
};

// The "gdof: progress ..." lines of an output; any other line starting so fails the test.
std::vector<ProgressLine> progress_lines(const std::string& output) {
    static const std::regex re(R"(^gdof: progress (?:frame (\d+) \((\d+)/(\d+)\) )?([a-z-]+) (\d+)%$)");
    std::vector<ProgressLine> lines;
    std::istringstream in(output);
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind("gdof: progress", 0) != 0) continue;
        std::smatch m;
        if (!std::regex_match(line, m, re)) {
            ADD_FAILURE() << "malformed progress line: '" << line << "'";
            continue;
        }
        ProgressLine p;
        if (m[1].matched) p.frame = std::stoi(m[1]), p.index = std::stoi(m[2]), p.count = std::stoi(m[3]);
        p.stage = m[4];
        p.percent = std::stoi(m[5]);
        lines.push_back(p);
    }
    return lines;
}

struct Scene {
    ScratchDir dir;
    std::string flat, field;
    explicit Scene(const std::string& size = "160x90") {
        flat = dir.file("scene.exr");
        field = dir.file("field.json");
        auto r = run_command(std::string("'") + GDOF_EXAMPLE_SCENE_PATH + "' --size " + size + " -o " + quote(flat));
        EXPECT_EQ(r.exit_code, 0) << r.output;
        write_text(field, R"({"blurfield": {"kind": "focal_planes", "depths": [2.9, 12.6], "max_blur": 6}})");
    }
};

}  // namespace

TEST(cli_farm, ProgressLinesPerFrameWhenNotATerminal) {
    Scene sc;
    // Two progress stages per frame (eval-blur, diffuse): one 0-100% scale.
    auto r = run_gdof("--frames 1001-1003 " + quote(sc.flat) + " --blurfield " + quote(sc.field) +
                      " --eval-blur --diffuse -o " + quote(sc.dir.file("out.####.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_FALSE(contains(r.output, "\r")) << "a redrawn bar in a log";
    const auto lines = progress_lines(r.output);
    ASSERT_FALSE(lines.empty()) << r.output;
    int done = 0, last_frame = 0, last_percent = -1;
    for (const ProgressLine& p : lines) {
        ASSERT_GE(p.frame, 1001) << r.output;
        EXPECT_EQ(p.count, 3);
        EXPECT_EQ(p.index, p.frame - 1000);
        EXPECT_GE(p.frame, last_frame) << r.output;
        if (p.frame != last_frame) last_percent = -1;
        EXPECT_GE(p.percent, last_percent) << "went back within frame " << p.frame << ":\n" << r.output;
        EXPECT_TRUE(p.stage == "eval-blur" || p.stage == "diffuse" || p.stage == "done") << p.stage;
        if (p.stage == "done") {
            EXPECT_EQ(p.percent, 100);
            EXPECT_EQ(p.frame, 1001 + done);
            ++done;
        }
        last_frame = p.frame, last_percent = p.percent;
    }
    EXPECT_EQ(done, 3) << r.output;

    // --no-progress: none.
    r = run_gdof("--no-progress --frames 1001-1002 " + quote(sc.flat) + " --eval-blur -o " +
                 quote(sc.dir.file("q.####.exr")));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_FALSE(contains(r.output, "gdof: progress")) << r.output;
}

TEST(cli_farm, ProgressLinesAtMostOneASecondAndMonotone) {
    Scene sc("960x540");
    const auto t0 = std::chrono::steady_clock::now();
    auto r = run_gdof("--threads 1 " + quote(sc.flat) + " --blurfield " + quote(sc.field) +
                      " --eval-blur --diffuse --bokeh -o " + quote(sc.dir.file("out.exr")));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto lines = progress_lines(r.output);
    ASSERT_GE(lines.size(), 2u) << r.output;  // the first report, and done
    // One a second, plus the final "done" line, plus one for a partial second.
    EXPECT_LE(double(lines.size()), seconds + 2.0) << seconds << " s:\n" << r.output;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        EXPECT_EQ(lines[i].frame, -1);  // no sequence: no frame field
        if (i > 0) {
            EXPECT_GE(lines[i].percent, lines[i - 1].percent) << r.output;
        }
    }
    EXPECT_EQ(lines.back().stage, "done");
    EXPECT_EQ(lines.back().percent, 100);
}

TEST(cli_farm, CommandLineWithoutOutputIsAUsageError) {
    Scene sc;
    auto r = run_gdof(quote(sc.flat) + " --blurfield " + quote(sc.field) + " --diffuse");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "no output")) << r.output;
    EXPECT_TRUE(contains(r.output, "-o FILE")) << r.output;
    EXPECT_EQ(list_dir(sc.dir.path().string()), (std::vector<std::string>{"field.json", "scene.exr"}));
    // Commands that print are a result.
    r = run_gdof("--info " + quote(sc.flat));
    EXPECT_EQ(r.exit_code, 0) << r.output;
    r = run_gdof(quote(sc.flat) + " --probe 10,10");
    EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST(cli_farm, SeveralFramesToOneNameIsAUsageError) {
    Scene sc;
    const std::string single = sc.dir.file("single.exr");
    auto r = run_gdof("--frames 1001-1003 " + quote(sc.flat) + " --eval-blur -o " + quote(single));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "single.exr")) << r.output;
    EXPECT_TRUE(contains(r.output, "3 frames")) << r.output;
    EXPECT_TRUE(contains(r.output, "####")) << r.output;
    EXPECT_FALSE(fs::exists(single));

    // An input sequence of two frames on disk, likewise.
    fs::copy_file(sc.flat, sc.dir.file("in.0001.exr"));
    fs::copy_file(sc.flat, sc.dir.file("in.0002.exr"));
    r = run_gdof(quote(sc.dir.file("in.####.exr")) + " -o " + quote(single));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "single.exr")) << r.output;
    EXPECT_FALSE(fs::exists(single));

    // One frame to one name is fine.
    r = run_gdof("--frames 7 " + quote(sc.flat) + " -o " + quote(single));
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(fs::exists(single));
}

TEST(cli_farm, MissingOutputFolderReportedBeforeAnyWork) {
    Scene sc;
    const std::string out = sc.dir.file("no_such_folder/out.####.exr");
    // The folder fails first, before the first step runs: the missing blur
    // field (read before the defocus) would fail otherwise.
    const auto t0 = std::chrono::steady_clock::now();
    auto r = run_gdof("--frames 1-3 " + quote(sc.flat) + " --blurfield " + quote(sc.dir.file("missing.json")) +
                      " --diffuse -o " + quote(out));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_TRUE(contains(r.output, "no_such_folder")) << r.output;
    EXPECT_TRUE(contains(r.output, "does not exist")) << r.output;
    EXPECT_FALSE(contains(r.output, "missing.json")) << r.output;
    EXPECT_LT(seconds, 2.0);
    EXPECT_FALSE(fs::exists(sc.dir.file("no_such_folder")));
}

TEST(cli_farm, OperationHelp) {
    auto r = run_gdof("--diffuse --help");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(r.output.rfind("gdof --diffuse", 0), 0u) << r.output;
    EXPECT_TRUE(contains(r.output, "--solver")) << r.output;  // the options of its group
    EXPECT_FALSE(contains(r.output, "--spp")) << r.output;    // not another method's
    const auto all = run_gdof("--help");
    EXPECT_LT(r.output.size() * 3, all.output.size());

    // A flag still missing its value, and the nearest flag before --help.
    r = run_gdof("--blurfield --help");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(r.output.rfind("gdof --blurfield FILE", 0), 0u) << r.output;
    r = run_gdof("in.exr --render scene.json --spp 4 -h");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(r.output.rfind("gdof --spp N", 0), 0u) << r.output;
    EXPECT_TRUE(contains(r.output, "--render SCENE")) << r.output;
}

TEST(cli_farm, HelpWrappedTo80ColumnsWhenNotATerminal) {
    auto check = [](const std::string& args) {
        auto r = run_gdof(args);
        ASSERT_EQ(r.exit_code, 0) << r.output;
        std::istringstream in(r.output);
        std::string line;
        int n = 0;
        while (std::getline(in, line)) {
            ++n;
            EXPECT_LE(line.size(), 80u) << args << ": '" << line << "'";
        }
        EXPECT_GT(n, 5);
    };
    check("--help");
    for (const char* op : {"--diffuse", "--bokeh", "--render", "--composite", "--lightfield", "--layers", "-o"})
        check(std::string(op) + " --help");
    // Every command is still listed.
    auto r = run_gdof("--help");
    for (const char* flag : {"--frames", "--diffuse", "--depth-invalid-value", "--adaptive-threshold", "--pyramid"})
        EXPECT_TRUE(contains(r.output, flag)) << flag;
}

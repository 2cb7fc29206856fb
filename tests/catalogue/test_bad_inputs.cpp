// The catalogue of bad inputs (bad_inputs.txt, docs/reliability.md): one
// table, one row per damaged file, absurd parameter or impossible request,
// run through the CLI, the Python module or the OpenFX plugin (in the test
// host). Each row must fail cleanly: the expected exit code (OFX: a failed
// render), a message containing the expected words, nothing left in the
// row's output folder and no file added beside its inputs.
#include <regex>

#include "catalogue/bad_input_fixtures.h"
#if GDOF_CATALOGUE_OFX
#include "ofx/ofx_test_support.h"
#endif

using namespace gdof::test;

namespace {

struct Row {
    int line = 0;
    std::string front;    // cli | python | ofx
    std::string name;
    std::string command;  // tokens; {fixture} is a file made for the row, {out} its output folder
    int exit_code = 0;
    std::string message;
};
// gtest prints a failing row by this.
[[maybe_unused]] void PrintTo(const Row& r, std::ostream* os) { *os << "line " << r.line << ": " << r.name; }

std::string trim(const std::string& s) {
    const auto b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
    return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

std::vector<Row> read_rows() {
    std::vector<Row> rows;
    std::ifstream in(std::string(GDOF_SOURCE_DIR) + "/tests/catalogue/bad_inputs.txt");
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
        if (trim(line).empty() || trim(line)[0] == '#') continue;
        std::vector<std::string> cells;
        std::size_t start = 0;
        for (std::size_t bar; (bar = line.find('|', start)) != std::string::npos; start = bar + 1)
            cells.push_back(trim(line.substr(start, bar - start)));
        cells.push_back(trim(line.substr(start)));
        Row r;
        r.line = n;
        if (cells.size() != 5) {
            r.name = "malformed row (want 5 cells separated by '|')";
            rows.push_back(r);
            continue;
        }
        r.front = cells[0];
        r.name = cells[1];
        r.command = cells[2];
        r.exit_code = std::atoi(cells[3].c_str());
        r.message = cells[4];
        rows.push_back(r);
    }
    return rows;
}

const std::vector<Row>& rows() {
    static const std::vector<Row> r = read_rows();
    return r;
}

// {name} -> a fixture's path, {out} -> the output folder.
std::string substitute(const std::string& text, Fixtures& fx, const std::string& out) {
    static const std::regex braces(R"(\{([A-Za-z0-9_.]+)\})");
    std::string result;
    auto it = std::sregex_iterator(text.begin(), text.end(), braces);
    std::size_t last = 0;
    for (; it != std::sregex_iterator(); ++it) {
        result += text.substr(last, std::size_t(it->position()) - last);
        const std::string name = (*it)[1];
        result += name == "out" ? out : fx.make(name);
        last = std::size_t(it->position() + it->length());
    }
    return result + text.substr(last);
}

std::vector<std::string> split_words(const std::string& s) {
    std::vector<std::string> words;
    std::istringstream in(s);
    for (std::string w; in >> w;) words.push_back(w);
    return words;
}

// Every file under dir, relative, sorted.
std::vector<std::string> tree(const std::string& dir) {
    std::vector<std::string> files;
    std::error_code ec;
    for (const auto& e : fs::recursive_directory_iterator(dir, ec)) files.push_back(fs::relative(e.path(), dir).string());
    std::sort(files.begin(), files.end());
    return files;
}

CommandResult run_cli(const std::string& command) {
    std::string args;
    for (const std::string& w : split_words(command)) args += " " + quote(w);
    return run_gdof(args);
}

CommandResult run_python(const std::string& code) {
#ifdef GDOF_PYTHON_EXE
    return run_command("PYTHONPATH=" + quote(GDOF_PYTHON_PATH) + " " + quote(GDOF_PYTHON_EXE) + " -c " +
                       quote("import gdof\n" + code));
#else
    (void)code;
    return {};
#endif
}

#if GDOF_CATALOGUE_OFX
// "defocus|focal_stack Clip=file.exr[:channels] name=value ...": the clips
// are read from EXR files (a ":Z" suffix makes an Alpha clip of that
// channel), parameters are set by their type in the plugin. The "exit code"
// is 0 for a rendered frame, 1 for a failed render; the message is the
// plugin's persistent message. Output: the host's output buffer starts as
// NaN, and a failed render must leave it so.
CommandResult run_ofx(const std::string& command) {
    CommandResult r;
    auto words = split_words(command);
    if (words.empty()) return r;
    const std::string id = words[0] == "defocus" ? kDefocusId : kFocalStackId;
    int w = 0, h = 0;
    std::vector<std::pair<std::string, ClipFrame>> clips;
    std::vector<std::pair<std::string, std::string>> params;
    for (std::size_t i = 1; i < words.size(); ++i) {
        const auto eq = words[i].find('=');
        const std::string key = words[i].substr(0, eq), value = words[i].substr(eq + 1);
        if (!std::isupper(static_cast<unsigned char>(key[0]))) {
            params.emplace_back(key, value);
            continue;
        }
        const auto colon = value.rfind(':');
        const std::string file = colon == std::string::npos ? value : value.substr(0, colon);
        const std::string channel = colon == std::string::npos ? "" : value.substr(colon + 1);
        OIIO::ImageSpec spec;
        const std::vector<float> px = read_pixels(file, &spec);
        ClipFrame f = ClipFrame::make(spec.width, spec.height, channel.empty() ? kOfxImageComponentRGBA : kOfxImageComponentAlpha);
        for (int y = 0; y < spec.height; ++y)
            for (int x = 0; x < spec.width; ++x)
                for (int c = 0; c < f.ncomp(); ++c) {
                    int src = channel.empty() ? c : -1;
                    for (int k = 0; k < spec.nchannels && !channel.empty(); ++k)
                        if (spec.channelnames[std::size_t(k)] == channel) src = k;
                    const std::size_t i0 = (std::size_t(spec.height - 1 - y) * std::size_t(spec.width) + std::size_t(x)) * std::size_t(spec.nchannels);
                    f.at(x, y, c) = src >= 0 && src < spec.nchannels ? px[i0 + std::size_t(src)] : 1.0f;
                }
        w = std::max(w, spec.width);
        h = std::max(h, spec.height);
        clips.emplace_back(key, f);
    }
    Session s{id, std::max(w, 1), std::max(h, 1)};
    if (!s.ok()) return r;
    for (auto& [name, frame] : clips) s.fx->connect(name, frame);
    for (auto& [name, value] : params) {
        const auto& p = *s.fx->effect().params.params.at(name);
        if (p.type == kOfxParamTypeDouble) s.fx->set(name, std::stod(value));
        else if (p.type == kOfxParamTypeInteger) s.fx->set_int(name, std::stoi(value));
        else if (p.type == kOfxParamTypeBoolean) s.fx->set_bool(name, value == "1" || value == "true");
        else if (p.type == kOfxParamTypeChoice) s.fx->set_choice(name, value);
        else s.fx->set_string(name, value);
    }
    const Rendered out = s.fx->render(0, {1, 1});
    r.exit_code = out.status == kOfxStatOK ? 0 : 1;
    r.output = s.fx->persistent_message();
    for (float v : out.px)
        if (!std::isnan(v)) {
            r.output += " [the failed render wrote pixels]";
            if (r.exit_code == 0) r.output = "";
            break;
        }
    return r;
}
#endif

class BadInput : public ::testing::TestWithParam<Row> {};

}  // namespace

TEST(bad_inputs, TheCatalogueHasAtLeastFiftyRowsOverEveryFrontEnd) {
    std::map<std::string, int> per_front;
    for (const Row& r : rows()) {
        EXPECT_NE(r.front, "") << "bad_inputs.txt line " << r.line << ": " << r.name;
        ++per_front[r.front];
    }
    EXPECT_GE(rows().size(), 50u);
    for (const char* front : {"cli", "python", "ofx"}) EXPECT_GT(per_front[front], 0) << front;
}

TEST_P(BadInput, FailsCleanly) {
    const Row& row = GetParam();
    ASSERT_FALSE(row.front.empty()) << "line " << row.line << ": " << row.name;
    ScratchDir dir;
    const std::string out = dir.file("out");
    fs::create_directories(out);
    Fixtures fx(dir.file("in"));
    fs::create_directories(fx.dir());
    const std::string command = substitute(row.command, fx, out);
    const std::vector<std::string> inputs_before = tree(fx.dir());
    CommandResult r;
    if (row.front == "cli") {
        r = run_cli(command);
    } else if (row.front == "python") {
#ifndef GDOF_PYTHON_EXE
        GTEST_SKIP() << "this build has no Python module (GDOF_BUILD_PYTHON=OFF)";
#endif
        r = run_python(command);
    } else if (row.front == "ofx") {
#if GDOF_CATALOGUE_OFX
        r = run_ofx(command);
#else
        GTEST_SKIP() << "this build has no OpenFX plugin (GDOF_BUILD_OFX=OFF)";
#endif
    } else {
        FAIL() << "line " << row.line << ": unknown front end '" << row.front << "'";
    }
    SCOPED_TRACE("bad_inputs.txt line " + std::to_string(row.line) + " (" + row.front + "): " + row.name + "\n  " + command);
    EXPECT_EQ(r.exit_code, row.exit_code) << r.output;
    EXPECT_TRUE(contains(r.output, row.message)) << "the message does not contain '" << row.message << "':\n" << r.output;
    EXPECT_FALSE(contains(r.output, "error: unexpected")) << "an exception the CLI did not expect:\n" << r.output;
    EXPECT_TRUE(tree(out).empty()) << "left in the output folder: " << ::testing::PrintToString(tree(out));
    EXPECT_EQ(tree(fx.dir()), inputs_before) << "files were added beside the inputs";
    if (std::getenv("GDOF_SHOW_MESSAGES")) std::printf("  %s\n", r.output.c_str());
}

INSTANTIATE_TEST_SUITE_P(catalogue, BadInput, ::testing::ValuesIn(rows()), [](const auto& row_info) {
    const Row& row = row_info.param;
    std::string name = "line" + std::to_string(row.line) + "_" + row.front + "_" + row.name;
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return name;
});

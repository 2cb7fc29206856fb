// --depth-from-focus SWEEP: a photographed focus sweep (a frame pattern in
// sweep order, or a stack manifest whose references carry their focus) ->
// the frames aligned to the middle one and the all-in-focus plate with Z
// (gdof/focus_sweep.h), pushed as the top image: -o writes it, --diffuse or
// --composite use it. --aligned-stack PATTERN before it also writes the
// aligned frames and their manifest.json (a stack for --composite, whose
// references are sharp about their focus distance, or about their index when
// none is known); --focus-distances gives a pattern's frames their focus;
// --dff-window-radius and --dff-min-peak-ratio tune the focus measure.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>

#include "cli.h"
#include "gdof/focus_sweep.h"
#include "gdof/image_ops.h"
#include "gdof/io/image_io.h"
#include "gdof/io/sequence.h"
#include "gdof/io/stack_sources.h"
#include "ops/ops.h"
#include "stack_output.h"

namespace gdof::cli {

namespace {

namespace fs = std::filesystem;

// The frames' files and their focus distances (empty: unknown, the index is the depth).
void sweep_files(const std::string& flag, const std::string& sweep, std::vector<std::string>& files,
                 std::vector<double>& focus, FocalStack& manifest) {
    std::string ext = fs::path(sweep).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".json") {
        auto st = io::load_stack(sweep);
        if (!st) runtime_error(flag + ": " + st.message());
        manifest = st.value();
        for (const StackReference& r : st.value().references) {
            files.push_back(r.path);
            // The reference's focus, else the distance its near and far limits
            // are symmetric about in dioptres.
            double d = r.focus_distance;
            if (!std::isfinite(d) && r.near > 0 && r.far > r.near) d = 2.0 / (1.0 / r.near + 1.0 / r.far);
            focus.push_back(d);
        }
        return;
    }
    if (!io::has_frame_pattern(sweep))
        usage_error(flag + " '" + sweep + "': give a frame pattern ('sweep/##.jpg', frames in focus order) or a stack manifest (.json)");
    auto frames = io::frames_on_disk(sweep);
    if (!frames) runtime_error(flag + " '" + sweep + "': " + frames.message());
    for (int k : frames.value()) {
        auto name = io::expand_frame_pattern(sweep, k);
        if (!name) runtime_error(flag + " '" + sweep + "': " + name.message());
        files.push_back(name.value());
    }
}

// The aligned frames' manifest: the input manifest's references (their lens
// and limits), or, for a pattern, each frame sharp up to halfway to its
// neighbours (in dioptres when its focus distance is known, else in frame
// indices: index - 0.5 to index + 0.5), the ends as far beyond.
FocalStack aligned_manifest(const FocalStack& input, const std::vector<double>& focus, std::size_t n, const Image& frame) {
    FocalStack st = input;
    st.width = frame.display_window().width();
    st.height = frame.display_window().height();
    if (st.references.size() == n) return st;
    st.references.assign(n, StackReference{});
    for (std::size_t k = 0; k < n; ++k) {
        StackReference& r = st.references[k];
        if (focus.size() != n) {
            r.near = double(k) + 0.5;
            r.far = double(k) + 1.5;
            continue;
        }
        // Dioptres of the frame and of the points halfway to each neighbour.
        const double d = 1.0 / focus[k];
        const double before = k > 0 ? 0.5 * (d + 1.0 / focus[k - 1]) : d - 0.5 * (1.0 / focus[k + 1] - d);
        const double after = k + 1 < n ? 0.5 * (d + 1.0 / focus[k + 1]) : d + 0.5 * (d - 1.0 / focus[k - 1]);
        const double hi = std::max(before, after), lo = std::min(before, after);
        r.focus_distance = focus[k];
        r.near = 1.0 / hi;
        r.far = lo > 0 ? 1.0 / lo : std::numeric_limits<double>::infinity();
    }
    return st;
}

void run_depth_from_focus(Frame& f, const std::string& sweep) {
    Session& s = *f.session;
    const std::string flag = "--depth-from-focus";
    const PendingSweep opt = f.sweep;
    f.sweep = PendingSweep{};
    std::vector<std::string> files;
    std::vector<double> focus;
    FocalStack manifest;
    sweep_files(flag, sweep, files, focus, manifest);
    if (!opt.focus_distances.empty()) {
        if (!manifest.references.empty())
            usage_error("--focus-distances: the manifest '" + sweep + "' gives each reference's focus; give one or the other");
        if (opt.focus_distances.size() != files.size())
            runtime_error("--focus-distances: " + std::to_string(opt.focus_distances.size()) + " distances for the " +
                          std::to_string(files.size()) + " frames of '" + sweep + "'");
        focus = opt.focus_distances;
    }
    std::optional<StackOutput> aligned_out;
    if (!opt.aligned_stack.empty()) {
        check_stack_pattern(opt.aligned_stack, "--aligned-stack");
        aligned_out.emplace(f, opt.aligned_stack, files.size());
    }
    if (files.size() < 2)
        runtime_error(flag + " '" + sweep + "': a sweep needs at least 2 frames, found " + std::to_string(files.size()));
    for (const std::string& p : files) {
        std::error_code ec;
        if (!fs::exists(p, ec)) runtime_error(flag + ": frame '" + p + "' not found");
    }
    if (std::any_of(focus.begin(), focus.end(), [](double d) { return !std::isfinite(d); })) focus.clear();

    s.progress.begin("depth-from-focus");
    std::vector<Image> frames;
    {
        StageTimer t(s.stats, "read");
        s.progress.part(0, 3);
        io::ReadOptions ro;
        ro.colour = s.colour.get();
        for (const std::string& p : files) {
            auto r = io::read_flat(p, ro);
            check_interrupted();
            if (!r) runtime_error(flag + ": " + r.message());
            if (!frames.empty() && r.value().data_window() != frames.front().data_window())
                runtime_error(flag + ": frame '" + p + "' is " + to_string(r.value().data_window()) + ", the first frame '" +
                              files.front() + "' " + to_string(frames.front().data_window()));
            frames.push_back(std::move(r).value());
        }
    }
    SweepAlignment alignment;
    {
        StageTimer t(s.stats, "align");
        s.progress.part(1, 3);
        auto r = align_sweep(frames, AlignOptions{}, s.exec);
        check_interrupted();
        if (!r) runtime_error(flag + " '" + sweep + "': " + r.message());
        alignment = std::move(r).value();
    }
    DepthFromFocus result;
    {
        StageTimer t(s.stats, "depth from focus");
        s.progress.part(2, 3);
        auto r = depth_from_focus(frames, focus, opt.options, s.exec);
        check_interrupted();
        if (!r) runtime_error(flag + " '" + sweep + "': " + r.message());
        result = std::move(r).value();
    }
    // The aligned stack is written once nothing can fail before the result.
    if (aligned_out) {
        StageTimer t(s.stats, "write");
        aligned_out->create_folder();
        for (std::size_t k = 0; k < frames.size(); ++k) {
            Image copy = frames[k];
            copy.metadata.set_string("gdof:focusSweep", sweep);
            check(aligned_out->write(k, std::move(copy)));
            check_interrupted();
        }
        aligned_out->write_manifest(aligned_manifest(manifest, focus, frames.size(), frames.front()));
    }
    Image& plate = result.plate;
    plate.metadata.set_string("gdof:focusSweep", sweep);
    plate.metadata.set_string("gdof:depthUnits", focus.empty() ? "sweep frame index" : "focus distance");
    if (s.global.stats || s.global.verbose) {
        s.progress.message("gdof: " + flag + ": " + alignment.report());
        s.progress.message("gdof: " + flag + ": " + result.stats.report() +
                           (focus.empty() ? "; depth is the frame index (no focus distances given)" : ""));
    }
    StackEntry e;
    e.images.parts.emplace_back(std::move(plate));
    e.source = sweep;
    f.stack.push_back(std::move(e));
}

}  // namespace

std::vector<Command> focus_sweep_commands() {
    const std::string L = "Photographed focus sweeps (method 2)";
    std::vector<Command> t;
    t.push_back({.names = {"--aligned-stack"}, .args = "PATTERN", .kind = Kind::Modifier, .group = L,
                 .help = "with --depth-from-focus: also write the aligned frames ('aligned/ref.####.exr') and their "
                         "manifest.json, a stack for --composite",
                 .run = [](Frame& f, const Step& s) { f.sweep.aligned_stack = s.args[0]; }});
    t.push_back({.names = {"--focus-distances"}, .args = "D1,D2,...", .kind = Kind::Modifier, .group = L,
                 .help = "--depth-from-focus: each frame's focus distance (scene units), in frame order, for a sweep "
                         "given as a pattern: Z in scene units, and the aligned stack's limits halfway to the "
                         "neighbours in dioptres",
                 .run = [](Frame& f, const Step& s) {
                     f.sweep.focus_distances.clear();
                     for (const std::string& v : take(split_list(s.args[0]), s.flag))
                         f.sweep.focus_distances.push_back(parse_double(s.flag, v));
                 }});
    t.push_back({.names = {"--dff-window-radius"}, .args = "N", .kind = Kind::Modifier, .group = L,
                 .help = "--depth-from-focus: the focus measure's window, (2 N + 1)^2 pixels (default 4)",
                 .run = [](Frame& f, const Step& s) { f.sweep.options.window_radius = parse_int(s.flag, s.args[0]); }});
    t.push_back({.names = {"--dff-min-peak-ratio"}, .args = "X", .kind = Kind::Modifier, .group = L,
                 .help = "--depth-from-focus: a pixel's sharpest frame must measure X times the median frame, else it is a "
                         "hole filled from its surroundings (default 3)",
                 .run = [](Frame& f, const Step& s) { f.sweep.options.min_peak_ratio = parse_double(s.flag, s.args[0]); }});
    t.push_back({.names = {"--depth-from-focus"}, .args = "SWEEP", .kind = Kind::Action, .group = L,
                 .help = "a focus sweep ('sweep/##.jpg' in focus order, or a stack manifest with focus distances): frames "
                         "aligned to the middle one, each pixel's sharpest frame; pushes the all-in-focus plate with Z "
                         "(focus distance, else frame index), focus.index, focus.confidence",
                 .stack = StackUse::PushesImage, .progress_stage = true,
                 .run = [](Frame& f, const Step& s) { run_depth_from_focus(f, s.args[0]); }});
    return t;
}

}  // namespace gdof::cli

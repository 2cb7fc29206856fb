// The gdof command line: shared declarations of the small CLI modules.
//
//   args.cpp      command table, argv -> Program (usage errors exit 2)
//   usage.cpp     --help / --version / short usage
//   frames.cpp    --frames and #### / @ / %0Nd sequences: runs the program per frame
//   run.cpp       executes one frame's steps on the image stack
//   cmd_io.cpp    inputs, -o, --info
//   cmd_colour.cpp --colorconvert (and the colour config)
//   cmd_channels.cpp --ch, --mulc
//   cmd_blur.cpp  --blurfield, --eval-blur (and the camera / field helpers)
//   cmd_diffuse.cpp --diffuse (method 3: heat diffusion of layers)
//   cmd_composite.cpp --composite (method 2: per-pixel pick from a focus/aperture stack)
//   cmd_render.cpp --render (method 1: ray tracing a scene)
//   cmd_lightfield.cpp --lightfield, --lf, --stack (method 2: stacks extracted from a light field)
//   progress.cpp  progress bar, frame counter, --stats timers
//   signals.cpp   Ctrl-C -> cancel flag
//   main.cpp      error reporting and exit codes
#pragma once

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "gdof/blur_field.h"
#include "gdof/camera.h"
#include "gdof/diffusion.h"
#include "gdof/exec.h"
#include "gdof/focal_stack.h"
#include "gdof/io/image_io.h"
#include "gdof/image_set.h"
#include "gdof/io/colour.h"
#include "gdof/layers.h"
#include "gdof/raytrace.h"
#include "gdof/status.h"

namespace gdof::cli {

// ---------------------------------------------------------------------------
// Errors: thrown inside the CLI only, turned into "gdof: error: ..." + exit code.

enum ExitCode : int { kOk = 0, kRuntimeError = 1, kUsageError = 2, kInterrupted = 130 };

struct CliError : std::runtime_error {
    int code;
    CliError(int c, const std::string& what) : std::runtime_error(what), code(c) {}
};
[[noreturn]] inline void usage_error(const std::string& what) { throw CliError(kUsageError, what); }
[[noreturn]] inline void runtime_error(const std::string& what) { throw CliError(kRuntimeError, what); }
// Throws a runtime error with the status message (and a context prefix) if it failed.
void check(const Status& s, const std::string& context = {});
template <class T>
T take(Result<T>&& r, const std::string& context = {}) {
    if (!r) check(r.status(), context);
    return std::move(r).value();
}

// ---------------------------------------------------------------------------
// Argument parsing

enum class Kind {
    Immediate,  // --help, --version: acted on while parsing
    Global,     // --threads, --frames ...: apply to the whole run
    Modifier,   // --iscolorspace, -d ...: change how later steps behave
    Action,     // an operation on the stack (or -o)
};

struct CommandDef {
    std::vector<std::string> names;  // first is the canonical name
    std::string args;                // "FILE", "FROM TO", "" (metavariables, space separated)
    int nargs = 0;
    Kind kind = Kind::Action;
    std::string group;  // section in --help
    std::string help;   // one line
    // Which of the arguments are file names (get frame substitution).
    std::vector<int> file_args;
    bool optional_value = false;  // a no-argument flag that also takes --flag=VALUE (--aovs)
};
const std::vector<CommandDef>& command_table();
const CommandDef* find_command(const std::string& name);
// A library error's message, followed by the flag that sets the setting it is
// about (its subject, e.g. "focal_length_mm" -> " (--focal-length-mm)").
std::string message_naming_flag(const Status& s);
// Parses a number for a flag; usage error naming the flag otherwise.
double parse_double(const std::string& flag, const std::string& value);

struct Step {
    const CommandDef* def = nullptr;  // nullptr: an input file
    std::string flag;                 // as typed
    std::vector<std::string> args;    // for an input: args[0] is the path
    // -o writing a stack (one file per reference, after --lightfield): its
    // frame pattern numbers the references, it is not a frame sequence.
    bool stack_output = false;
    bool is_input() const { return def == nullptr; }
    const std::string& name() const;  // canonical name, or "input"
};

struct GlobalOptions {
    int threads = 0;  // 0: all cores
    std::string frames;  // --frames spec ("" none)
    std::string colorconfig;
    bool stats = false;
    bool progress = false;     // --progress forces the bar on
    bool no_progress = false;  // --no-progress forces it off
    bool verbose = false;
    bool skip_bad_frames = false;
};

struct Program {
    GlobalOptions global;
    std::vector<Step> steps;
};

// Parses argv. Acts on --help / --version at once (prints, returns nullopt
// with exit_code set). Throws CliError(kUsageError) for usage errors.
std::optional<Program> parse_args(const std::vector<std::string>& argv, int& exit_code);

// ---------------------------------------------------------------------------
// Usage text

std::string usage_text();        // --help
std::string short_usage_text();  // no arguments

// ---------------------------------------------------------------------------
// Progress, frame counter and --stats

class Progress {
public:
    void enable(bool on) { enabled_ = on; }
    bool enabled() const { return enabled_; }
    // Starts a bar with a label ("eval-blur"); update() is thread-safe.
    void begin(const std::string& label);
    void update(double fraction);
    void end();
    void message(const std::string& line);  // a full line on stderr (clears the bar)

private:
    bool enabled_ = false;
    bool active_ = false;
    int last_percent_ = -1;
    std::chrono::steady_clock::time_point last_draw_{};
    std::string label_;
    std::mutex mu_;
};

class Stats {
public:
    void add(const std::string& stage, double seconds);
    void add_frame() { ++frames_; }
    std::string report(double total_seconds) const;

private:
    std::vector<std::pair<std::string, double>> stages_;  // in order of first use
    int frames_ = 0;
    mutable std::mutex mu_;
};

// Times a scope into Stats under a stage name.
class StageTimer {
public:
    StageTimer(Stats& stats, std::string stage)
        : stats_(stats), stage_(std::move(stage)), t0_(std::chrono::steady_clock::now()) {}
    ~StageTimer() {
        stats_.add(stage_, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count());
    }
    StageTimer(const StageTimer&) = delete;
    StageTimer& operator=(const StageTimer&) = delete;

private:
    Stats& stats_;
    std::string stage_;
    std::chrono::steady_clock::time_point t0_;
};

// ---------------------------------------------------------------------------
// Ctrl-C

void install_signal_handlers();
bool interrupted();
// Throws CliError(kInterrupted) if Ctrl-C was pressed.
void check_interrupted();

// ---------------------------------------------------------------------------
// Execution state

struct StackEntry {
    ImageSet images;
    std::string source;  // file it came from ("" for results)
    // Colour space of the colour channels after --colorconvert (canonical
    // name); "" while they are in the scene-linear working space.
    std::string colorspace;
};

// Opaque blur-field state owned by cmd_blur.cpp.
struct BlurState;

// State that lives for the whole run (all frames).
struct Session {
    GlobalOptions global;
    std::shared_ptr<const io::ColourConfig> colour;
    Progress progress;
    Stats stats;
    Exec exec;  // threads, cancel flag, progress
    // Blur fields already parsed, by path (a sequence parses each file once).
    std::map<std::string, std::shared_ptr<BlurState>> blur_cache;
};


// State of one run of the steps (one frame).
struct Frame {
    Session* session = nullptr;
    std::optional<int> frame;  // frame number when running a sequence
    std::vector<StackEntry> stack;

    // Modifiers.
    std::string next_input_colorspace;  // --iscolorspace (next input only)
    std::string output_pixel_type;      // -d (this and later outputs)
    std::string output_compression;     // --compression
    std::string output_colorspace;      // --ocolorspace
    bool info_on_read = false;          // --info before any input: describe each input

    // Eval-blur modifiers (names as the camera / blur-field JSON keys).
    std::string position_channels;
    std::string depth_channel;
    DepthDecode depth_decode;  // --depth-encoding / --depth-scale / --depth-near / --depth-far
    std::map<std::string, double> camera_overrides;  // "focal_length_mm" -> 35
    std::shared_ptr<BlurState> blur;

    // --diffuse modifiers (names as the library's settings).
    DiffusionSolver solver = DiffusionSolver::Auto;  // --solver
    LayerSplit layer_split;                         // --layers
    int adi_steps = 0;                              // --adi-steps (0: automatic)

    // --composite (method 2) and its options, which may follow it
    // (gdof --composite m.json --surfaces s.json): it runs before the next
    // other step, or at the end.
    struct PendingComposite {
        std::string manifest;  // pending --composite ("" none)
        std::string surfaces, near_map, far_map;
        int soft_k = 1;
        bool aovs = false;
    } composite;

    // --lightfield (cmd_lightfield.cpp): the next -o writes its stack.
    std::string lightfield;                       // pending light-field source ("" none)
    std::string lightfield_config, stack_spec;    // --lf, --stack

    // --render (method 1) and its options; it runs before the next other step.
    struct PendingRender {
        std::string scene;  // pending --render ("" none)
        int spp = 64, min_spp = 4, light_samples = 2;
        double adaptive_threshold = 0.01;
        bool pinhole = false, straight_thin_lens = false;
        bool deep = false;         // --deep: a deep image (for method 3)
        RenderAov aovs = RenderAov::All;  // --aovs=LIST
        std::string stack_spec;    // --stack after --render: the next -o writes a stack
    } render;

    StackEntry& top(const std::string& flag);
};

// Runs one frame's steps. Throws CliError.
void run_steps(Session& session, const std::vector<Step>& steps, std::optional<int> frame);

// Command implementations (each file registers its part of the table in args.cpp).
void do_input(Frame& f, const std::string& path);
// A whole text file (JSON); errors "FLAG: WHAT 'path' not found" (cmd_io.cpp).
std::string read_text(const std::string& flag, const std::string& what, const std::string& path);
void do_output(Frame& f, const std::string& path);
void do_info(Frame& f);
void do_colorconvert(Frame& f, const std::string& from, const std::string& to);
void do_ch(Frame& f, const std::string& list);
void do_mulc(Frame& f, const std::string& list);
void do_blurfield(Frame& f, const std::string& path);
void do_eval_blur(Frame& f);
void do_diffuse(Frame& f);
// --composite, --surfaces, --near-map, --far-map, --soft, --aovs: returns true
// if `step` was one of them; otherwise (and for nullptr = end of the steps)
// runs a pending --composite first and returns false (cmd_composite.cpp).
bool composite_step(Frame& f, const Step* step);
// --render and its options (--spp, --min-spp, --pinhole, ...): returns true
// if `step` was one of them; otherwise (and for nullptr = end of the steps)
// runs a pending --render first, except before --blurfield (cmd_render.cpp).
bool render_step(Frame& f, const Step* step);
// -o after --lightfield: extracts the stack, writes one file per reference
// (frame number = reference index from 1) and manifest.json (cmd_lightfield.cpp).
void do_lightfield_output(Frame& f, const std::string& pattern);
// -o after --render ... --stack: renders the focus/aperture stack (cmd_render.cpp).
void do_render_stack_output(Frame& f, const std::string& pattern);

// A stack's files (stack_output.cpp): -o's frame pattern numbers the
// references from 1, all in one folder; manifest.json beside them is written
// last and atomically. `producer` names the command in errors.
void check_stack_pattern(const std::string& pattern, const std::string& producer);
class StackOutput {
public:
    StackOutput(Frame& f, const std::string& pattern, std::size_t n_references);
    void create_folder() const;  // before the first write (after planning: bad specs write nothing)
    Status write(std::size_t index, Image&& image) const;  // with -d, --compression, --ocolorspace
    void write_manifest(FocalStack stack) const;            // file names filled in; throws CliError
    const std::string& name(std::size_t i) const { return names_[i]; }
    const std::string& manifest_path() const { return manifest_; }

private:
    Frame& frame_;
    std::string pattern_, dir_, manifest_;
    std::vector<std::string> names_;
    io::WriteOptions wo_;
};
// Shared by --eval-blur and --diffuse (cmd_blur.cpp). Errors name `flag`.
std::string image_name(const StackEntry& e);  // "'in.exr'" or "the top image"
LensOverrides lens_overrides(const Frame& f);
// The camera of a part: its metadata with the --focal-length-mm ... overrides.
Camera part_camera(const Frame& f, const Metadata& md, const Roi& display, const std::string& flag,
                   const std::string& where);
// --blurfield, else a thin lens from the camera's lens data.
BlurField field_for(const Frame& f, const Camera& camera, const std::string& flag, const std::string& where);
// Canonical name of the scene-linear working space of a config ("" if none).
std::string working_space(const io::ColourConfig& config);
// Checks colour space names against the config before any work is done.
void preflight_colour(const Session& session, const std::vector<Step>& steps);

// Frame-sequence driver: runs the program once (no sequence) or per frame.
int run_program(Program& program, Session& session);

}  // namespace gdof::cli

// The command table: one row per flag -- its names, arguments, help, order
// facts and what it does. Each operation's file (ops/*.cpp) registers its rows;
// registry.cpp collects them in the order --help lists them.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace gdof::cli {

struct Frame;
struct Session;
struct Command;

enum class Kind {
    Immediate,  // --help, --version: acted on while parsing
    Global,     // --threads, --frames ...: apply to the whole run
    Modifier,   // --iscolorspace, -d ...: change how later steps behave
    Action,     // an operation on the stack (or -o)
};

// What a step does to the image stack, for the order checks made while parsing.
enum class StackUse {
    None,
    NeedsImage,   // an image must be on the stack (-o, --diffuse ...)
    PushesImage,  // leaves an image on the stack (--render, --composite, --lightfield)
};

// --render and --composite wait for their options, which may follow them:
// a pending one runs when a step comes that does not let it wait (or at the
// end of the steps), the render first. Bits of Command::lets_wait.
enum Deferred : unsigned { kNothingWaits = 0, kRenderWaits = 1, kCompositeWaits = 2 };

struct Step {
    const Command* def = nullptr;   // nullptr: an input file
    std::string flag;               // as typed
    std::vector<std::string> args;  // for an input: args[0] is the path
    // -o writing a stack (one file per reference, after --lightfield or
    // --render --stack): its frame pattern numbers the references, it is not
    // a frame sequence.
    bool stack_output = false;
    bool is_input() const { return def == nullptr; }
    const std::string& name() const;  // canonical name, or "input"
};

struct GlobalOptions {
    int threads = 0;     // 0: all cores
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

struct Command {
    std::vector<std::string> names{};  // first is the canonical name
    std::string args{};                // "FILE", "FROM TO", "" (metavariables, space separated)
    Kind kind = Kind::Action;
    std::string group{};  // section in --help
    std::string help{};   // one line
    // Which of the arguments are file names (they get the frame number).
    std::vector<int> file_args{};
    bool optional_value = false;    // a no-argument flag that also takes --flag=VALUE (--aovs)
    bool allows_empty_value = false;  // "" is a value (--compression "": the image's own)
    StackUse stack = StackUse::None;
    bool is_work = false;  // something to do on its own (--info, --blurfield); so is any StackUse
    bool progress_stage = false;  // reports progress: one slot of its frame's 0-100% (progress.h)
    bool prints_result = false;   // its result is printed, not written (--info, --probe): needs no -o

    // What it does, by kind (exactly one is set):
    std::function<std::string()> print{};                    // Immediate: the text for stdout
    std::function<void(GlobalOptions&, const Step&)> set{};  // Global: checks the value, sets it
    std::function<void(Frame&, const Step&)> run{};          // Modifier, Action: on one frame
    // Optional:
    // While parsing: checks the values that need no file (usage errors naming the flag).
    std::function<void(const Step&)> check{};
    // Before any work, with the session (the colour config): checks names in it.
    std::function<void(const Session&, const Step&)> preflight{};
    // The pending operations this step lets wait (Deferred bits); unset: none.
    std::function<unsigned(const Frame&, const Step&)> lets_wait{};

    int nargs() const;  // from args
};

// All rows, in --help order (registry.cpp).
const std::vector<Command>& command_table();
const Command* find_command(const std::string& name);
// The row an input file runs as (-i).
const Command& input_command();

// Parses argv. Acts on --help / --version at once (prints, returns nullopt
// with exit_code set). Throws CliError(kUsageError) for usage errors.
std::optional<Program> parse_args(const std::vector<std::string>& argv, int& exit_code);
// The order rules between steps (structure.cpp), after parsing; usage errors.
void mark_stack_outputs(Program& p);
void validate_structure(const Program& p);

}  // namespace gdof::cli

// The gdof command line: the declarations its modules share.
//
//   command.h / registry.cpp  the command table: one row per flag (names, arguments, help,
//                 order facts, check, runner), collected from the operations
//   args.cpp      argv -> Program (usage errors exit 2)
//   structure.cpp order rules between steps (image on the stack, modifiers' commands, stack outputs)
//   values.cpp    flag values: numbers parsed strictly
//   errors.cpp    CliError, library statuses -> messages (naming the flag of a setting)
//   usage.cpp     --help, OPERATION --help, --version, short usage (wrapped to the terminal)
//   frames.cpp    --frames and #### / @ / %0Nd sequences: runs the program per frame
//   run.cpp       runs one frame's steps: each step's row's runner, deferred --render / --composite
//   ops/          one file per operation: its rows, value checks and runner (ops/ops.h lists them)
//   frame.h       Session and Frame: the state steps run on (settings in the library's own structs)
//   camera_field.cpp  the camera and blur field of an image (shared by the methods); blur_state.h
//   stack_output.cpp  writing a focus/aperture stack (-o after --lightfield or --render --stack)
//   text_input.cpp    JSON files named by flags
//   progress.cpp  progress: one 0-100% scale per frame, a bar or log lines; --stats timers
//   signals.cpp   SIGINT / SIGTERM -> cancel flag, exit 130 / 143
//   main.cpp      session setup, error reporting and exit codes (the only file outside gdof_cli_lib)
#pragma once

#include <string>
#include <vector>

#include "command.h"
#include "errors.h"
#include "frame.h"
#include "progress.h"
#include "text_input.h"
#include "values.h"

namespace gdof::cli {

// Usage text (usage.cpp).
std::string usage_text();        // --help
std::string command_help_text(const Command& c);  // OPERATION --help
std::string short_usage_text();  // no arguments
std::string version_text();      // --version

// SIGINT / SIGTERM (signals.cpp).
void install_signal_handlers();
bool interrupted();
int interrupt_exit_code();  // 130 after SIGINT, 143 after SIGTERM
// Throws CliError(130 / 143) if SIGINT / SIGTERM came.
void check_interrupted();
[[noreturn]] void throw_interrupted();

// Checks every step's names against the session (colour spaces in the
// config) before any work is done (run.cpp).
void preflight(const Session& session, const std::vector<Step>& steps);

// Frame-sequence driver: runs the program once (no sequence) or per frame (frames.cpp).
int run_program(Program& program, Session& session);

}  // namespace gdof::cli

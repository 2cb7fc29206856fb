// The CLI's argument parser in process, without running anything: the input
// is argv, one argument per line. Usage errors are CliError exceptions (exit
// 2 in the program); anything else escaping is a finding. --help and
// --version print: stdout is muted.
#include <iostream>
#include <sstream>

#include "cli.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static std::ostringstream sink;
    static const bool muted = [] {
        std::cout.rdbuf(sink.rdbuf());
        return true;
    }();
    (void)muted;
    sink.str({});
    std::vector<std::string> argv;
    std::string rest = gdof::fuzz::text(data, size);
    while (!rest.empty()) {
        auto [arg, tail] = gdof::fuzz::split(rest, "\n");
        argv.push_back(arg);
        rest = tail;
    }
    try {
        int exit_code = 0;
        (void)gdof::cli::parse_args(argv, exit_code);
    } catch (const gdof::cli::CliError&) {
    }
    return 0;
}

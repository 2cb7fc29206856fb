// argv -> Program. Each argument is an input file or a flag of the command
// table with its arguments: --help / --version act at once, global flags set
// GlobalOptions, the others become steps whose values are checked now; the
// order rules between steps follow (structure.cpp).
#include <cerrno>
#include <cstdlib>
#include <iostream>

#include "cli.h"

namespace gdof::cli {

namespace {

bool looks_like_flag(const std::string& a) {
    if (a.size() < 2 || a[0] != '-') return false;
    // A negative number is not a flag (frame ranges, values).
    char* end = nullptr;
    errno = 0;
    std::strtod(a.c_str(), &end);
    return !(end && *end == '\0');
}

Step input_step(const std::string& path) {
    if (path.empty()) usage_error("empty file name argument");
    if (path == "-") usage_error("'-' (standard input) is not supported; give a file name");
    Step s;
    s.flag = path;
    s.args = {path};
    return s;
}

// The flag at argv[i] with its arguments: --flag=VALUE (one-argument flags)
// or the arguments that follow; i moves to the last one taken.
Step flag_step(const std::vector<std::string>& argv, std::size_t& i) {
    const std::string& a = argv[i];
    std::string flag = a, inline_value;
    bool has_inline = false;
    if (auto eq = a.find('='); eq != std::string::npos && a.rfind("--", 0) == 0) {
        flag = a.substr(0, eq);
        inline_value = a.substr(eq + 1);
        has_inline = true;
    }
    const Command* def = find_command(flag);
    if (!def) usage_error("unknown flag '" + flag + "' (see gdof --help)");
    Step s;
    s.def = def;
    s.flag = flag;
    if (has_inline) {
        if (def->nargs() != 1 && !def->optional_value) usage_error(flag + " does not take '=VALUE'");
        s.args.push_back(inline_value);
        return s;
    }
    for (int k = 0; k < def->nargs(); ++k) {
        if (i + 1 >= argv.size())
            usage_error(flag + ": missing argument " + std::to_string(k + 1) + " (" + flag + " " + def->args + ")");
        const std::string& v = argv[++i];
        // A flag where a value was expected is almost always a mistake,
        // except a negative number (handled by looks_like_flag).
        if (looks_like_flag(v) && find_command(v))
            usage_error(flag + ": missing argument (" + flag + " " + def->args + "), got flag '" + v + "'");
        s.args.push_back(v);
    }
    return s;
}

// A step of the program: its values checked; -i FILE becomes an input.
Step program_step(Step s) {
    const Command& c = *s.def;
    if (c.check) c.check(s);
    if (&c == &input_command()) s.def = nullptr;  // an input like any bare file name
    for (const std::string& v : s.args)
        if (v.empty() && !c.allows_empty_value) usage_error(s.flag + ": empty argument");
    return s;
}

// `gdof OPERATION --help`: the help of the nearest flag before --help (the
// whole help without one). Looked for first, so that a flag still missing
// its value (gdof --blurfield --help) does not make a usage error.
bool print_help(const std::vector<std::string>& argv) {
    for (std::size_t i = 0; i < argv.size(); ++i) {
        if (argv[i] != "--help" && argv[i] != "-h") continue;
        for (std::size_t j = i; j-- > 0;) {
            const std::string name = argv[j].substr(0, argv[j].rfind("--", 0) == 0 ? argv[j].find('=') : std::string::npos);
            const Command* c = looks_like_flag(name) ? find_command(name) : nullptr;
            if (c && c->kind != Kind::Immediate) {
                std::cout << command_help_text(*c);
                std::cout.flush();
                return true;
            }
        }
        std::cout << usage_text();
        std::cout.flush();
        return true;
    }
    return false;
}

}  // namespace

std::optional<Program> parse_args(const std::vector<std::string>& argv, int& exit_code) {
    if (print_help(argv)) {
        exit_code = kOk;
        return std::nullopt;
    }
    Program p;
    for (std::size_t i = 0; i < argv.size(); ++i) {
        if (!looks_like_flag(argv[i])) {
            p.steps.push_back(input_step(argv[i]));
            continue;
        }
        Step s = flag_step(argv, i);
        const Command& c = *s.def;
        if (c.kind == Kind::Immediate) {
            std::cout << c.print();
            std::cout.flush();
            exit_code = kOk;
            return std::nullopt;
        }
        if (c.kind == Kind::Global) c.set(p.global, s);
        else p.steps.push_back(program_step(std::move(s)));
    }
    mark_stack_outputs(p);
    validate_structure(p);
    return p;
}

}  // namespace gdof::cli

// The command table: the rows of every operation (ops/), in --help order.
#include <algorithm>

#include "command.h"
#include "ops/ops.h"

namespace gdof::cli {

int Command::nargs() const {
    if (args.empty()) return 0;
    return 1 + int(std::count(args.begin(), args.end(), ' '));
}

const std::vector<Command>& command_table() {
    static const std::vector<Command> table = [] {
        std::vector<Command> t;
        for (auto rows : {general_commands, sequence_commands, colour_commands, io_commands, channel_commands,
                          render_commands, blur_commands, depth_source_commands, lens_commands, diffuse_commands, aperture_commands, plate_commands,
                          composite_commands, lightfield_commands, focus_sweep_commands})
            for (Command& c : rows()) t.push_back(std::move(c));
        return t;
    }();
    return table;
}

const Command* find_command(const std::string& name) {
    for (const Command& c : command_table())
        if (std::find(c.names.begin(), c.names.end(), name) != c.names.end()) return &c;
    return nullptr;
}

const Command& input_command() {
    static const Command* input = find_command("-i");
    return *input;
}

const std::string& Step::name() const {
    static const std::string input = "input";
    return def ? def->names.front() : input;
}

}  // namespace gdof::cli

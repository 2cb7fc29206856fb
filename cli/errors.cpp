// Library statuses -> CLI errors (errors.h).
#include "errors.h"

#include <algorithm>

#include "cli.h"

namespace gdof::cli {

void check(const Status& s, const std::string& context) {
    if (s) return;
    check_interrupted();
    runtime_error(context.empty() ? s.message() : context + ": " + s.message());
}

std::string message_naming_flag(const Status& s) {
    if (s.subject().empty()) return s.message();
    std::string flag = "--" + s.subject();
    std::replace(flag.begin(), flag.end(), '_', '-');
    return find_command(flag) ? s.message() + " (" + flag + ")" : s.message();
}

}  // namespace gdof::cli

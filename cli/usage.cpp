// --help (all commands, or one operation's: gdof --diffuse --help),
// --version and the short usage shown when gdof is run without arguments.
// Help is wrapped to the terminal's width (80 columns when stdout is not a
// terminal).
#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <sstream>

#include "cli.h"
#include "gdof/version.h"

namespace gdof::cli {

namespace {

constexpr std::size_t kMaxNameColumn = 30;  // longer names put their help on the next line

std::size_t help_width() {
    winsize ws{};
    if (::isatty(STDOUT_FILENO) && ::ioctl(STDOUT_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 0)
        return std::max<std::size_t>(ws.ws_col, 40);
    return 80;
}

// `text` in lines of at most `width` columns, the first starting at column
// `first` (already written by the caller), the others indented by `indent`.
// A word longer than a line is left whole.
std::string wrap(const std::string& text, std::size_t first, std::size_t indent, std::size_t width) {
    std::istringstream words(text);
    std::string word, out;
    std::size_t col = first;
    bool line_empty = true;
    while (words >> word) {
        if (!line_empty && col + 1 + word.size() > width) {
            out += "\n" + std::string(indent, ' ');
            col = indent;
            line_empty = true;
        }
        if (!line_empty) out += ' ', ++col;
        out += word;
        col += word.size();
        line_empty = false;
    }
    return out + "\n";
}

std::string head_of(const Command& d) {
    std::string head = d.names.front();
    for (std::size_t k = 1; k < d.names.size(); ++k) head += ", " + d.names[k];
    if (!d.args.empty()) head += " " + d.args;
    return head;
}

// Rows as "  HEAD  help", the help in a column after the longest head (up to
// kMaxNameColumn; a longer head has its help on the next line), wrapped.
std::string format_rows(const std::vector<const Command*>& rows, std::size_t width) {
    std::size_t column = 0;
    for (const Command* d : rows) {
        const std::size_t n = head_of(*d).size();
        if (n <= kMaxNameColumn) column = std::max(column, n);
    }
    const std::size_t indent = 2 + column + 2;
    std::string o;
    for (const Command* d : rows) {
        const std::string head = head_of(*d);
        o += "  " + head;
        if (head.size() <= column) {
            o += std::string(column + 2 - head.size(), ' ');
        } else {
            o += "\n" + std::string(indent, ' ');
        }
        o += wrap(d->help, indent, indent, width);
    }
    return o;
}

}  // namespace

std::string short_usage_text() {
    return "usage: gdof [options] INPUT... [operations] -o OUTPUT\n"
           "       gdof --info FILE...\n"
           "       gdof --help | --version | OPERATION --help\n"
           "Try 'gdof --help' for the list of commands.\n";
}

std::string version_text() { return "gdof " + std::string(gdof::version()) + "\n"; }

std::string usage_text() {
    const std::size_t width = help_width();
    std::ostringstream o;
    o << "gdof " << gdof::version() << ": generalized depth of field for film post\n\n"
      << "usage: gdof [options] INPUT... [operations] -o OUTPUT\n"
      << "       gdof OPERATION --help   (one operation and its options)\n\n"
      << wrap("Arguments run left to right on a stack of images, as in oiiotool: a file name pushes the image (all "
              "its parts), operations replace the top image, -o writes the top image. A command line must write "
              "something (-o) or print something (--info, --probe). Outputs are written to a temporary file and "
              "renamed, so a failed or interrupted run never leaves a partial file; output folders are checked "
              "before any work.",
              0, 0, width);
    std::string group;
    std::vector<const Command*> rows;
    auto flush = [&] {
        if (!rows.empty()) o << "\n" << group << ":\n" << format_rows(rows, width);
        rows.clear();
    };
    for (const Command& d : command_table()) {
        if (d.group != group) {
            flush();
            group = d.group;
        }
        rows.push_back(&d);
    }
    flush();
    o << "\nExamples:\n"
      << "  gdof --info -v shot.exr\n"
      << "  gdof plate.exr --colorconvert linear sRGB -o preview.png\n"
      << "  gdof render.exr --blurfield field.json --eval-blur -o withblur.exr\n"
      << "  gdof --frames 1001-1100 in.####.exr --blurfield field.json --eval-blur \\\n"
      << "       -o out.####.exr\n"
      << "  gdof in.exr --blurfield field.json --diffuse -o out.exr\n"
      << "  gdof deep.exr --layers 6 --solver explicit --diffuse -o out.exr\n"
      << "  gdof deep.exr --blurfield field.json --psf-field swirl.json --vibrate -o out.exr\n"
      << "\n"
      << wrap("Exit status: 0 success, 1 runtime error, 2 usage error, 130 interrupted (SIGINT, Ctrl-C), 143 "
              "terminated (SIGTERM).",
              0, 0, width);
    return o.str();
}

std::string command_help_text(const Command& c) {
    const std::size_t width = help_width();
    std::ostringstream o;
    o << "gdof " << head_of(c) << "\n\n" << wrap(c.help, 0, 0, width);
    std::vector<const Command*> related;
    for (const Command& d : command_table())
        if (d.group == c.group) related.push_back(&d);
    o << "\n" << c.group << ":\n" << format_rows(related, width);
    o << "\nTry 'gdof --help' for every command.\n";
    return o.str();
}

}  // namespace gdof::cli

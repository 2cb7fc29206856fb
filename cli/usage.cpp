// --help and the short usage shown when gdof is run without arguments.
#include <sstream>

#include "cli.h"
#include "gdof/version.h"

namespace gdof::cli {

std::string short_usage_text() {
    return "usage: gdof [options] INPUT... [operations] -o OUTPUT\n"
           "       gdof --info FILE...\n"
           "       gdof --help | --version\n"
           "Try 'gdof --help' for the list of commands.\n";
}

std::string version_text() { return "gdof " + std::string(gdof::version()) + "\n"; }

std::string usage_text() {
    std::ostringstream o;
    o << "gdof " << gdof::version() << ": generalized depth of field for film post\n\n"
      << "usage: gdof [options] INPUT... [operations] -o OUTPUT\n\n"
      << "Arguments run left to right on a stack of images, as in oiiotool: a file\n"
      << "name pushes the image (all its parts), operations replace the top image,\n"
      << "-o writes the top image. Outputs are written to a temporary file and\n"
      << "renamed, so a failed or interrupted run never leaves a partial file.\n";
    std::string group;
    std::size_t width = 0;
    for (const Command& d : command_table()) {
        std::string head = d.names.front() + (d.args.empty() ? "" : " " + d.args);
        width = std::max(width, head.size() + (d.names.size() > 1 ? d.names[1].size() + 2 : 0));
    }
    for (const Command& d : command_table()) {
        if (d.group != group) {
            group = d.group;
            o << "\n" << group << ":\n";
        }
        std::string head = d.names.front();
        for (std::size_t k = 1; k < d.names.size(); ++k) head += ", " + d.names[k];
        if (!d.args.empty()) head += " " + d.args;
        o << "  " << head << std::string(width + 2 > head.size() ? width + 2 - head.size() : 1, ' ') << d.help
          << "\n";
    }
    o << "\nExamples:\n"
      << "  gdof --info -v shot.exr\n"
      << "  gdof plate.exr --colorconvert linear sRGB -o preview.png\n"
      << "  gdof render.exr --blurfield field.json --eval-blur -o withblur.exr\n"
      << "  gdof --frames 1001-1100 in.####.exr --blurfield field.json --eval-blur -o out.####.exr\n"
      << "  gdof in.exr --blurfield field.json --diffuse -o out.exr\n"
      << "  gdof deep.exr --layers 6 --solver explicit --diffuse -o out.exr\n"
      << "  gdof deep.exr --blurfield field.json --psf-field swirl.json --vibrate -o out.exr\n"
      << "\nExit status: 0 success, 1 runtime error, 2 usage error, 130 interrupted (Ctrl-C).\n";
    return o.str();
}

}  // namespace gdof::cli

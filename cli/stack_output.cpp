// Writing a focus/aperture stack: one image per reference named by the -o
// frame pattern (reference i -> frame i + 1), all in one folder, and
// manifest.json beside them, written last (temporary file + rename) so a
// failed run never leaves a manifest pointing at missing or half-written
// images. Shared by --lightfield and --render --stack.
#include <filesystem>

#include "stack_output.h"

#include "cli.h"
#include "gdof/io/image_io.h"
#include "gdof/io/sequence.h"

namespace gdof::cli {

namespace fs = std::filesystem;

void check_stack_pattern(const std::string& pattern, const std::string& producer) {
    if (!io::has_frame_pattern(pattern))
        usage_error("-o '" + pattern + "': " + producer + " is one file per reference: give a frame pattern, "
                    "e.g. stack/ref.####.exr");
}

StackOutput::StackOutput(Frame& f, const std::string& pattern, std::size_t n) : frame_(f), pattern_(pattern) {
    for (std::size_t i = 0; i < n; ++i)
        names_.push_back(take(io::expand_frame_pattern(pattern, int(i) + 1), "-o '" + pattern + "'"));
    dir_ = fs::path(names_.front()).parent_path().string();
    for (const std::string& name : names_)
        if (fs::path(name).parent_path().string() != dir_)
            usage_error("-o '" + pattern + "': the stack's files must share one folder (the frame pattern is in a folder name)");
    manifest_ = (fs::path(dir_) / "manifest.json").string();
    wo_ = f.output;
}

void StackOutput::create_folder() const {
    std::error_code ec;
    if (!dir_.empty() && !fs::is_directory(dir_, ec)) {
        fs::create_directories(dir_, ec);
        if (ec) runtime_error("-o '" + pattern_ + "': cannot create folder '" + dir_ + "': " + ec.message());
    }
}

Status StackOutput::write(std::size_t i, Image&& image) const {
    ImageSet set;
    set.parts.emplace_back(std::move(image));
    return io::write_image(names_[i], set, wo_);  // its messages name the file
}

void StackOutput::write_manifest(FocalStack stack) const {
    for (std::size_t i = 0; i < stack.references.size() && i < names_.size(); ++i)
        stack.references[i].file = fs::path(names_[i]).filename().string();
    check(io::write_text(manifest_, format_stack_manifest(stack)));
    if (frame_.session->global.verbose) frame_.session->progress.message("gdof: wrote " + manifest_);
}

}  // namespace gdof::cli

// A stack's files (stack_output.cpp): -o's frame pattern numbers the
// references from 1, all in one folder; manifest.json beside them is written
// last and atomically.
#pragma once

#include <string>
#include <vector>

#include "frame.h"
#include "gdof/focal_stack.h"
#include "gdof/image.h"

namespace gdof::cli {

// `producer` names the command in errors.
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

}  // namespace gdof::cli

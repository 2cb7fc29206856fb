// Blur-field files with their masks (gdof/io/blur_field_io.h).
#include "gdof/io/blur_field_io.h"

#include <memory>

#include "blurfield/field_file.h"
#include "gdof/io/image_io.h"

namespace gdof::io {

BlurField::Context blur_field_context(const std::string& base_dir) {
    BlurField::Context ctx;
    ctx.base_dir = base_dir;
    ctx.load_image = [](const std::string& p) -> Result<std::shared_ptr<const Image>> {
        ReadOptions ro;
        ro.linearize = false;  // painted masks are data
        auto r = read_flat(p, ro);
        if (!r) return r.status();
        return std::shared_ptr<const Image>(std::make_shared<Image>(std::move(r).value()));
    };
    return ctx;
}

Result<BlurField> parse_blur_field(const std::string& json_text, const std::string& base_dir) {
    return BlurField::parse(json_text, blur_field_context(base_dir));
}

Result<BlurField> read_blur_field(const std::string& path) { return read_field_file(path, parse_blur_field); }

}  // namespace gdof::io

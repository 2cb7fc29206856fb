// --aperture: the iris shape (gdof/aperture.h) for --render (the ray
// tracer's lens samples) and --bokeh (the filter's point-spread function).
// An image kernel's file is read here, once per frame that uses it.
#include "cli.h"
#include "gdof/aperture.h"
#include "gdof/io/image_io.h"
#include "ops/ops.h"

namespace gdof::cli {

namespace {

Aperture parse(const Step& s) {
    auto r = parse_aperture(s.args[0]);
    if (!r) usage_error(s.flag + ": " + r.message());
    return std::move(r).value();
}

}  // namespace

Aperture with_kernel_image(Frame& f, Aperture a, const std::string& context) {
    if (a.kind == Aperture::Kind::Image && a.image.data_window().empty()) {
        io::ReadOptions ro;
        ro.colour = f.session->colour.get();
        auto r = io::read_image(a.image_path, ro);
        if (!r) runtime_error(context + ": " + r.message());
        if (r->empty() || r->is_deep(0)) runtime_error(context + ": '" + a.image_path + "' holds no flat image");
        a.image = r->flat(0);
        // A colour kernel spreads by R, G, B; anything else by its first channel.
        const RgbaIndices c = find_rgba(a.image);
        if (c.r >= 0 && c.g >= 0 && c.b >= 0) {
            Image rgb = Image::with_channels({"R", "G", "B"}, a.image.data_window());
            const int src[3] = {c.r, c.g, c.b};
            for (int k = 0; k < 3; ++k)
                for (int y = rgb.data_window().y0; y < rgb.data_window().y1; ++y)
                    for (int x = rgb.data_window().x0; x < rgb.data_window().x1; ++x)
                        rgb.at(k, x, y) = a.image.sample(src[k], x, y);
            a.image = std::move(rgb);
        }
    }
    check(validate(a), context);
    return a;
}

namespace {

void set_aperture(Frame& f, const Step& s) {
    Aperture a = with_kernel_image(f, parse(s), s.flag);
    f.defocus.aperture = a;
    f.render.options.aperture = std::move(a);
    f.render.aperture_given = true;
}

}  // namespace

std::vector<Command> aperture_commands() {
    std::vector<Command> t;
    t.push_back({.names = {"--aperture"}, .args = "SHAPE", .kind = Kind::Modifier,
                 .group = "Aperture (--render, --bokeh)",
                 .help = "iris shape: disc (default), polygon:BLADES[:ROTATION_DEG] or image:FILE (a grey or colour "
                         "kernel), then ,roundness=0..1 ,squeeze=S (anamorphic) ,cats_eye=0..1 (--bokeh, --vibrate), e.g. "
                         "polygon:6:15,roundness=0.2",
                 .run = set_aperture,
                 .check = [](const Step& s) { parse(s); },
                 .lets_wait = render_option_waits});
    return t;
}

}  // namespace gdof::cli

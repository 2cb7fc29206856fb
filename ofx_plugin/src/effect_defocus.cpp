// "gdof Defocus": method 3 (heat diffusion of depth layers, gdof/defocus.h)
// on the Source clip, with the depth from the Depth clip and the blur field
// from the parameters: the same defocus() call as `gdof --diffuse` (filter
// bokeh: `--bokeh`; filter vibrate: method 4, `--vibrate`).
#include <cmath>

#include "defocus_inputs.h"
#include "defocus_params.h"
#include "effects.h"
#include "gdof/defocus.h"
#include "gdof/plate.h"
#include "ofx_clips.h"
#include "ofx_params.h"

namespace gdof::ofx {

namespace {

const char* const kSource = kOfxImageEffectSimpleSourceClipName;
const char* const kDepth = "Depth";
const char* const kBlurMap = "BlurMap";
const char* const kMask = "Mask";
const char* const kAperture = "Aperture";
const char* const kOutput = kOfxImageEffectOutputClipName;

class DefocusEffect final : public Effect {
public:
    const char* label() const override { return "gdof Defocus"; }
    const char* description() const override {
        return "Generalized depth of field by simulated heat diffusion (Kosloff & Barsky): blur placed anywhere in "
               "depth -- a thin lens, several focal planes, a region of focus, or a painted blur map -- from a "
               "depth or position pass.";
    }

    void describe_in_context(OfxImageEffectHandle desc, const std::string&) override {
        define_clip(desc, kSource, "Source", {kOfxImageComponentRGBA, kOfxImageComponentRGB}, false);
        define_clip(desc, kDepth, "Depth",
                    {kOfxImageComponentRGBA, kOfxImageComponentRGB, kOfxImageComponentAlpha}, true);
        define_clip(desc, kBlurMap, "Blur Map",
                    {kOfxImageComponentRGBA, kOfxImageComponentRGB, kOfxImageComponentAlpha}, true);
        define_clip(desc, kMask, "Mask", {kOfxImageComponentAlpha, kOfxImageComponentRGBA}, true)
            .set(kOfxImageClipPropIsMask, 1);
        define_clip(desc, kAperture, "Aperture",
                    {kOfxImageComponentRGBA, kOfxImageComponentRGB, kOfxImageComponentAlpha}, true);
        define_clip(desc, kOutput, "Output", {kOfxImageComponentRGBA, kOfxImageComponentRGB}, false);
        ParamDefiner d(desc);
        describe_defocus_params(d);
    }

    void clip_preferences(OfxImageEffectHandle fx, Props out) override {
        const Clip src(fx, kSource);
        const bool rgb = src.components() == kOfxImageComponentRGB;
        out.set(clip_prop("OfxImageClipPropComponents_", kOutput).c_str(), rgb ? kOfxImageComponentRGB : kOfxImageComponentRGBA);
        for (const char* c : {kSource, kDepth, kBlurMap, kMask, kAperture, kOutput})
            out.set(clip_prop("OfxImageClipPropDepth_", c).c_str(), kOfxBitDepthFloat);
        // The result is premultiplied RGBA (colour blurred with its coverage).
        out.set(kOfxImageEffectPropPreMultiplication, rgb ? kOfxImageOpaque : kOfxImagePreMultiplied);
    }

    bool region_of_definition(OfxImageEffectHandle fx, double time, OfxPointD scale, OfxRectD& rod) override {
        const Clip src(fx, kSource);
        if (!src.connected()) return false;
        const PixelFrame f = pixel_frame(fx, scale);
        const DefocusParams p = read_defocus_params(ParamReader(fx, time));
        const Roi in = gdof_pixels(f, src.region_of_definition(time));
        rod = f.to_canonical(f.to_ofx(defocus_output_region(in, f.display, max_radius_px(p, f.sx))));
        return true;
    }

    void regions_of_interest(OfxImageEffectHandle fx, double time, OfxPointD scale, const OfxRectD& roi,
                             Props out) override {
        const PixelFrame f = pixel_frame(fx, scale);
        const DefocusParams p = read_defocus_params(ParamReader(fx, time));
        const OfxRectD margin = f.to_canonical(f.to_ofx(defocus_input_region(gdof_pixels(f, roi), max_radius_px(p, f.sx))));
        auto set = [&](const char* clip, const OfxRectD& r) {
            out.set_doubles(clip_prop("OfxImageClipPropRoI_", clip).c_str(), {r.x1, r.y1, r.x2, r.y2});
        };
        for (const char* c : {kSource, kDepth}) {
            const Clip clip(fx, c);
            // frame: the layers are analysed on the whole frame, so every tile sees the same layers.
            set(c, p.analysis == "frame" && clip.connected() ? clip.region_of_definition(time) : margin);
        }
        const Clip map(fx, kBlurMap);
        if (map.connected()) set(kBlurMap, map.region_of_definition(time));
        const Clip kernel(fx, kAperture);
        if (kernel.connected()) set(kAperture, kernel.region_of_definition(time));
        set(kMask, roi);
    }

    void render(OfxImageEffectHandle fx, const RenderArgs& a) override {
        const PixelFrame f = pixel_frame(fx, a.scale);
        DefocusParams p = read_defocus_params(ParamReader(fx, a.time));
        const Clip src(fx, kSource), depth(fx, kDepth), map(fx, kBlurMap), mask(fx, kMask), output(fx, kOutput);

        const ClipImage out(output, a.time);
        if (!out.valid()) fail("the host gave no output image");
        out.require({kOfxImageComponentRGBA, kOfxImageComponentRGB});
        if (!src.connected()) fail("the Source clip is not connected");
        const ClipImage simg(src, a.time);
        const Roi window = f.to_gdof(a.window);
        if (!simg.valid()) {  // nothing at this time: transparent black
            write_rgba(Image::with_channels({"R", "G", "B", "A"}, Roi{}), f, out, a.window);
            return;
        }
        simg.require({kOfxImageComponentRGBA, kOfxImageComponentRGB});
        const bool need_depth = p.kind != "image_map" || depth.connected();
        if (need_depth && !depth.connected())
            fail("the Depth clip is not connected: connect a depth pass (or a position pass with depth_pass = "
                 "position); the blur field needs each pixel's depth");

        // The input: the whole source frame (analysis = frame), or the
        // render window grown by the blur margin.
        const double rmax = max_radius_px(p, f.sx);
        Roi in_win = f.to_gdof(simg.bounds());
        if (p.analysis == "region") in_win = intersect(in_win, defocus_input_region(window, rmax));

        auto camera = resolve_camera(Metadata{}, f.display, lens_overrides(p));
        if (!camera) fail("camera: " + camera.message());
        Image img = premultiplied_rgba(simg, f, in_win);
        if (need_depth) {
            const ClipImage dimg(depth, a.time);
            if (!dimg.valid()) fail("clip 'Depth' has no image at this time");
            add_depth(img, dimg, p, f, *camera);
        } else {
            add_flat_depth(img);
        }
        if (p.use_focus_at) {
            // The same focus as --focus-at: the median depth around the point.
            if (p.kind != "thin_lens") fail("focus_at: only the thin_lens kind has a focus distance");
            const int x = int(std::floor(p.focus_at[0] * f.sx / f.par));
            const int y = f.gdof_y(int(std::floor(p.focus_at[1] * f.sy)));
            auto opts = defocus_settings(p);
            if (!opts) fail(opts.message());
            auto focused = focus_camera_at(Metadata{}, f.display, lens_overrides(p), img, img.channel_index("Z"),
                                           opts->source.depth_decode, opts->cleanup, x, y);
            if (!focused) fail("focus_at: " + focused.message());
            p.focus_distance = focused->focus.distance;
            camera = std::move(focused->camera);
        }

        BlurField::Context ctx;
        if (p.kind == "image_map") {
            if (!map.connected()) fail("blur field image_map: the Blur Map clip is not connected");
            const ClipImage mimg(map, a.time);
            if (!mimg.valid()) fail("clip 'BlurMap' has no image at this time");
            ctx.images["blur_map"] = std::make_shared<const Image>(map_image(mimg, f));
        }
        auto field = BlurField::parse(blur_field_json(p, f.sx), ctx);
        if (!field) fail("blur field: " + field.message());
        auto settings = defocus_settings(p);
        if (!settings) fail(settings.message());
        settings->roi = window;
        if (settings->filter != DefocusFilter::Diffusion && settings->aperture.kind == Aperture::Kind::Image) {
            // The kernel's pixels as they are: its size does not matter (it is
            // fitted to the blur radius), so render scale scales it too.
            const Clip kernel(fx, kAperture);
            if (!kernel.connected()) fail("aperture image: the Aperture clip is not connected");
            const ClipImage kimg(kernel, a.time);
            if (!kimg.valid()) fail("clip 'Aperture' has no image at this time");
            settings->aperture.image = map_image(kimg, f);
            settings->aperture.image_path = "clip 'Aperture'";
        }

        const Exec exec = render_exec(fx);
        ImageSet in;
        in.parts.emplace_back(std::move(img));
        auto result = defocus(in, *field, *camera, *settings, nullptr, exec);
        if (exec.is_cancelled()) return;  // the host no longer wants this frame
        if (!result) fail(result.message());
        Image& res = result->flat(0);

        if (mask.connected()) {
            const ClipImage mimg(mask, a.time);
            if (mimg.valid()) apply_mask(res, in.flat(0), mimg, f);
        }
        write_rgba(res, f, out, a.window);
    }

private:
    // result = mask * result + (1 - mask) * source, mask = the Mask clip's alpha (0 outside it).
    static void apply_mask(Image& res, const Image& source, const ClipImage& mask, const PixelFrame& f) {
        mask.require({kOfxImageComponentAlpha, kOfxImageComponentRGBA});
        const int mc = mask.ncomponents() - 1;
        const Roi w = res.data_window();
        for (int y = w.y0; y < w.y1; ++y)
            for (int x = w.x0; x < w.x1; ++x) {
                const int oy = f.gdof_y(y);
                const float m = mask.contains(x, oy) ? mask.pixel(x, oy)[mc] : 0.0f;
                for (int c = 0; c < 4; ++c) {
                    const float s = source.data_window().contains(x, y) ? source.at(c, x, y) : 0.0f;
                    res.at(c, x, y) = m * res.at(c, x, y) + (1.0f - m) * s;
                }
            }
    }
};

}  // namespace

Effect& defocus_effect() {
    static DefocusEffect e;
    return e;
}

}  // namespace gdof::ofx

// "gdof Focal Stack": method 2 (gdof/compositing.h). Each output pixel is
// pulled from the reference of a focus/aperture stack whose [near, far] best
// matches the desired one: the same composite() as `gdof --composite`, written
// straight into the host's output image. The stack is the frames of the
// Source clip (lens per frame from the lens table or a manifest; their pixels
// read in place, stack_pixels.h) or the files of a manifest; the desired
// near/far come from B-spline control points, a surfaces file or the Near /
// Far clips.
#include <algorithm>
#include <limits>
#include <memory>
#include <string>

#include "effects.h"
#include "focal_stack_params.h"
#include "gdof/compositing.h"
#include "gdof/io/stack_reader.h"
#include "gdof/io/stack_sources.h"
#include "gdof/text_file.h"
#include "ofx_clips.h"
#include "ofx_params.h"
#include "stack_pixels.h"

namespace gdof::ofx {

namespace {

const char* const kSource = kOfxImageEffectSimpleSourceClipName;
const char* const kNear = "Near";
const char* const kFar = "Far";
const char* const kOutput = kOfxImageEffectOutputClipName;

// A files stack, opened.
struct FileStack {
    FocalStack stack;
    std::unique_ptr<io::StackReader> reader;
    Roi grid;  // the references' data window (pixels at scale 1; gdof = EXR coordinates)
};

FileStack open_files(const FocalStackParams& p) {
    if (p.manifest.empty()) fail("parameter 'manifest': give a stack manifest (stack_source = files)");
    auto s = io::load_stack(p.manifest);
    if (!s) fail("parameter 'manifest': " + s.message());
    FileStack fs;
    fs.stack = std::move(s).value();
    if (Status st = io::check_stack_files(fs.stack); !st) fail("parameter 'manifest': " + st.message());
    auto r = io::StackReader::create(fs.stack);
    if (!r) fail("parameter 'manifest': " + r.message());
    fs.reader = std::move(r).value();
    auto info = fs.reader->info(0);
    if (!info) fail("parameter 'manifest': " + info.message());
    fs.grid = info->data_window;
    return fs;
}

FrameStack open_frames(const FocalStackParams& p, OfxImageEffectHandle fx) {
    const PixelFrame f1 = pixel_frame(fx, {1, 1});
    auto fs = frame_stack(p, f1.display.width(), f1.display.height());
    if (!fs) fail(fs.message());
    if (fs->frames.empty()) fail("the stack has no references");
    return std::move(fs).value();
}

class FocalStackEffect final : public Effect {
public:
    const char* label() const override { return "gdof Focal Stack"; }
    const char* description() const override {
        return "Generalized depth of field from a focus/aperture stack (Kosloff & Barsky, section 3): each pixel is "
               "taken from the stack image whose depth of field best matches near/far focus surfaces.";
    }
    bool temporal_clip_access() const override { return true; }

    void describe_in_context(OfxImageEffectHandle desc, const std::string& context) override {
        define_clip(desc, kSource, "Source", {kOfxImageComponentRGBA, kOfxImageComponentRGB},
                    context == kOfxImageEffectContextGeneral, true);
        for (const char* c : {kNear, kFar})
            define_clip(desc, c, c, {kOfxImageComponentRGBA, kOfxImageComponentRGB, kOfxImageComponentAlpha}, true);
        define_clip(desc, kOutput, "Output", {kOfxImageComponentRGBA, kOfxImageComponentRGB}, false);
        ParamDefiner d(desc);
        describe_focal_stack_params(d);
    }

    void clip_preferences(OfxImageEffectHandle fx, Props out) override {
        const Clip src(fx, kSource);
        const bool rgb = src.connected() && src.components() == kOfxImageComponentRGB;
        out.set(clip_prop("OfxImageClipPropComponents_", kOutput).c_str(), rgb ? kOfxImageComponentRGB : kOfxImageComponentRGBA);
        for (const char* c : {kSource, kNear, kFar, kOutput})
            out.set(clip_prop("OfxImageClipPropDepth_", c).c_str(), kOfxBitDepthFloat);
        out.set(kOfxImageEffectPropPreMultiplication, rgb ? kOfxImageOpaque : kOfxImagePreMultiplied);
    }

    bool region_of_definition(OfxImageEffectHandle fx, double time, OfxPointD scale, OfxRectD& rod) override {
        const FocalStackParams p = read_focal_stack_params(ParamReader(fx, time));
        if (p.stack_source == "files") {
            const PixelFrame f1 = pixel_frame(fx, {1, 1});
            rod = f1.to_canonical(f1.to_ofx(open_files(p).grid));
            return true;
        }
        const Clip src(fx, kSource);
        if (!src.connected()) return false;
        rod = stack_rod(src, open_frames(p, fx));
        return true;
    }

    void regions_of_interest(OfxImageEffectHandle fx, double time, OfxPointD, const OfxRectD& roi, Props out) override {
        const FocalStackParams p = read_focal_stack_params(ParamReader(fx, time));
        auto set = [&](const char* clip, const OfxRectD& r) {
            out.set_doubles(clip_prop("OfxImageClipPropRoI_", clip).c_str(), {r.x1, r.y1, r.x2, r.y2});
        };
        set(kSource, p.stack_source == "frames" ? roi : OfxRectD{0, 0, 0, 0});
        for (const char* c : {kNear, kFar}) {
            const Clip clip(fx, c);  // maps: the whole map (it must match the stack's grid)
            if (clip.connected()) set(c, clip.region_of_definition(time));
        }
    }

    bool frames_needed(OfxImageEffectHandle fx, double time, Props out) override {
        const FocalStackParams p = read_focal_stack_params(ParamReader(fx, time));
        if (p.stack_source != "frames") return false;
        std::vector<int> frames = open_frames(p, fx).frames;
        std::sort(frames.begin(), frames.end());
        std::vector<double> ranges;  // [first, last] pairs of runs of consecutive frames
        for (std::size_t i = 0; i < frames.size(); ++i) {
            if (!ranges.empty() && frames[i] <= ranges.back() + 1) ranges.back() = std::max(ranges.back(), double(frames[i]));
            else ranges.insert(ranges.end(), {double(frames[i]), double(frames[i])});
        }
        out.set_doubles(clip_prop("OfxImageClipPropFrameRange_", kSource).c_str(), ranges);
        return true;
    }

    void render(OfxImageEffectHandle fx, const RenderArgs& a) override {
        const PixelFrame f = pixel_frame(fx, a.scale);
        const FocalStackParams p = read_focal_stack_params(ParamReader(fx, a.time));
        const ClipImage out(Clip(fx, kOutput), a.time);
        if (!out.valid()) fail("the host gave no output image");
        out.require({kOfxImageComponentRGBA, kOfxImageComponentRGB});
        const Exec exec = render_exec(fx);
        const ImageView target = out.view(f, a.window);  // composite() writes the host's pixels
        if (p.stack_source == "files") render_files(fx, p, f, a, target, exec);
        else render_frames(fx, p, f, a, target, exec);
    }

private:
    // The stack's extent: the union of the Source's RoD at the stack's frames
    // (frames the clip does not have add nothing).
    static OfxRectD stack_rod(const Clip& src, const FrameStack& fs) {
        OfxRectD u{0, 0, 0, 0};
        bool any = false;
        for (int frame : fs.frames) {
            const OfxRectD r = src.region_of_definition(frame);
            if (r.x2 <= r.x1 || r.y2 <= r.y1) continue;
            u = any ? OfxRectD{std::min(u.x1, r.x1), std::min(u.y1, r.y1), std::max(u.x2, r.x2), std::max(u.y2, r.y2)} : r;
            any = true;
        }
        return u;
    }

    // The source of the desired near/far over the stack's grid (gdof
    // coordinates): Near / Far maps are copied into `maps` (one channel, NaN
    // outside the host's image).
    static FocusSource focus_source(OfxImageEffectHandle fx, const FocalStackParams& p, const PixelFrame& f, double time,
                                    const Roi& grid, Image (&maps)[2]) {
        if (p.focus_source == "maps") {
            const char* names[2] = {kNear, kFar};
            for (int i = 0; i < 2; ++i) {
                const Clip clip(fx, names[i]);
                if (!clip.connected()) fail(std::string("focus from maps: the ") + names[i] + " clip is not connected");
                const ClipImage img(clip, time);
                if (!img.valid()) fail(std::string("clip '") + names[i] + "' has no image at this time");
                img.require({kOfxImageComponentRGBA, kOfxImageComponentRGB, kOfxImageComponentAlpha});
                static const std::string rgba = "RGBA";
                const int comp = img.ncomponents() == 1 ? (p.map_channel == "A" ? 0 : -1)
                                                        : int(rgba.find(p.map_channel));
                if (comp < 0 || comp >= img.ncomponents())
                    fail(std::string("clip '") + names[i] + "' has no channel " + p.map_channel + " (parameter 'map_channel')");
                maps[i] = Image::with_channels({"depth"}, grid);
                read_components(img, f, maps[i], {{comp, 0}}, std::numeric_limits<float>::quiet_NaN());
            }
            return FocusMaps{&maps[0], 0, &maps[1], 0};
        }
        if (p.focus_source == "surfaces_file" && p.surfaces.empty()) fail("parameter 'surfaces': give a surfaces file");
        std::string text;
        if (p.focus_source == "surfaces") {
            text = surfaces_json(p);
        } else {
            auto r = read_text(p.surfaces);
            if (!r) fail("parameter 'surfaces': " + r.message());
            text = std::move(r).value();
        }
        auto s = parse_focus_surfaces(text);
        if (!s) fail((p.focus_source == "surfaces" ? std::string("near/far control points: ") : "parameter 'surfaces': ") + s.message());
        return std::move(s).value();
    }

    static CompositeOptions composite_options(const FocalStackParams& p) {
        CompositeOptions cs;
        cs.soft_k = p.soft;
        return cs;
    }

    // composite()'s error (none when cancelled: the host drops the output),
    // with the plugin's name for the input at fault (its subject).
    static void check_composite(const Status& st, const FocalStackParams& p, const Exec& exec) {
        if (st || exec.is_cancelled()) return;
        const std::string& about = st.subject();
        std::string prefix;
        if (about == "focus" && p.focus_source == "maps") prefix = "Near / Far maps: ";
        else if (about == "stack") prefix = "stack: ";
        else if (about == "pixels" && p.stack_source == "files") prefix = "parameter 'manifest': ";
        fail(prefix + st.message());
    }

    void render_frames(OfxImageEffectHandle fx, const FocalStackParams& p, const PixelFrame& f, const RenderArgs& a,
                       const ImageView& target, const Exec& exec) {
        FrameStack fs = open_frames(p, fx);
        const Clip src(fx, kSource);
        if (!src.connected()) fail("the Source clip is not connected (stack_source = frames)");
        const Roi grid = gdof_pixels(f, stack_rod(src, fs));
        // The references are the Source frames as the host gives them at this
        // render scale (the grid), whatever resolution a lens manifest names.
        fs.stack.width = fs.stack.height = 0;
        Image maps[2];
        const FocusSource focus = focus_source(fx, p, f, a.time, grid, maps);
        SourceFramePixels pixels(src, fs.frames, f, grid);
        const Status st = composite(fs.stack, focus, pixels, CompositeTarget{target}, composite_options(p), nullptr, exec);
        pixels.rethrow_fetch_error();
        check_composite(st, p, exec);
    }

    void render_files(OfxImageEffectHandle fx, const FocalStackParams& p, const PixelFrame& f, const RenderArgs& a,
                      const ImageView& target, const Exec& exec) {
        FileStack fs = open_files(p);
        if ((f.sx != 1.0 || f.sy != 1.0) && p.focus_source == "maps")
            fail("Near / Far maps with stack_source = files need render scale 1 (the files are full resolution)");
        Image maps[2];
        const FocusSource focus = focus_source(fx, p, f, a.time, fs.grid, maps);
        // Below render scale 1: the full-resolution composite, reduced.
        const CompositeTarget t{target, f.sx, f.sy};
        check_composite(composite(fs.stack, focus, *fs.reader, t, composite_options(p), nullptr, exec), p, exec);
    }
};

}  // namespace

Effect& focal_stack_effect() {
    static FocalStackEffect e;
    return e;
}

}  // namespace gdof::ofx

// Method 2 end to end (compositing.h, composite()): the desired focus from its
// source, the size checks, selection and tiles; the whole result as an Image,
// or a region (at a render scale: a proxy) into the caller's memory.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <variant>
#include <vector>

#include "compositing_internal.h"
#include "gdof/compositing.h"

namespace gdof {

namespace {

using clock = std::chrono::steady_clock;

double seconds_since(clock::time_point t0) { return std::chrono::duration<double>(clock::now() - t0).count(); }

// The composite() input an error is about (compositing.h).
constexpr const char* kFocus = "focus";
constexpr const char* kStack = "stack";
constexpr const char* kPixels = "pixels";

Status about(const Status& st, const char* subject) { return Status::error(st.message(), st.code(), subject); }

std::string size_str(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

std::string reference_name(const FocalStack& stack, int ref) {
    const std::string& path = std::size_t(ref) < stack.references.size() ? stack.references[std::size_t(ref)].path : "";
    return path.empty() ? "reference " + std::to_string(ref) : "reference '" + path + "'";
}

// ref0: reference 0's info when the caller has it (surfaces without a
// manifest size take theirs from it).
Result<DesiredFocus> desired_focus(const FocalStack& stack, const FocusSource& focus, StackPixels& pixels,
                                   const ReferenceInfo* ref0, const Exec& exec) {
    Result<DesiredFocus> d = Status::error("no desired focus");
    if (const auto* surfaces = std::get_if<FocusSurfaces>(&focus)) {
        int w = stack.width, h = stack.height;
        if (w <= 0 || h <= 0) {
            Result<ReferenceInfo> info = ref0 ? Result<ReferenceInfo>(*ref0) : pixels.info(0);
            if (!info) return info.status();  // about the reference, not the surfaces
            w = info->data_window.width();
            h = info->data_window.height();
        }
        d = desired_from_surfaces(*surfaces, w, h, exec);
    } else if (const auto* maps = std::get_if<FocusMaps>(&focus)) {
        if (!maps->near || !maps->far)
            return Status::error("near/far maps: an image is missing", StatusCode::InvalidArgument, kFocus);
        d = desired_from_maps(*maps->near, maps->near_channel, *maps->far, maps->far_channel);
    } else {
        const auto& b = std::get<FocusFromBlurField>(focus);
        if (!b.field || !b.camera || !b.depth_image)
            return Status::error("blur field focus: the field, camera or depth image is missing",
                                 StatusCode::InvalidArgument, kFocus);
        d = desired_from_blur_field(*b.field, *b.camera, *b.depth_image, b.options, exec);
    }
    if (!d) return about(d.status(), kFocus);
    // The manifest's size, when it gives one, is the stack's.
    const int W = d->window.width(), H = d->window.height();
    if (stack.width > 0 && stack.height > 0 && (stack.width != W || stack.height != H))
        return Status::error("the desired focus is " + size_str(W, H) + " but the stack is " +
                                 size_str(stack.width, stack.height),
                             StatusCode::InvalidArgument, kFocus);
    return d;
}

Status check_reference_size(const FocalStack& stack, int ref, const ReferenceInfo& info, const DesiredFocus& d) {
    const Roi& dw = info.data_window;
    if (dw.width() == d.window.width() && dw.height() == d.window.height()) return Status::ok();
    return Status::error(reference_name(stack, ref) + " is " + size_str(dw.width(), dw.height()) +
                             " but the desired focus is " + size_str(d.window.width(), d.window.height()),
                         StatusCode::InvalidArgument, kFocus);
}

Result<StackIndex> stack_index(const FocalStack& stack) {
    std::vector<DepthInterval> limits;
    for (const StackReference& r : stack.references) limits.push_back({r.near, r.far});
    auto index = StackIndex::build(limits);
    if (!index) return about(index.status(), kStack);
    return index;
}

// The part of `d` over `window` (in d's coordinates, inside d.window).
DesiredFocus crop(const DesiredFocus& d, const Roi& window) {
    DesiredFocus c;
    c.window = intersect(window, d.window);
    c.near.resize(c.npixels());
    c.far.resize(c.npixels());
    for (int y = c.window.y0; y < c.window.y1; ++y)
        for (int x = c.window.x0; x < c.window.x1; ++x) {
            c.near[c.offset(x, y)] = d.near[d.offset(x, y)];
            c.far[c.offset(x, y)] = d.far[d.offset(x, y)];
        }
    return c;
}

// Reads tile t of `inner` at t + (dx, dy): a sub-window of the stack.
class ShiftedPixels final : public StackPixels {
public:
    ShiftedPixels(StackPixels& inner, int dx, int dy) : inner_(inner), dx_(dx), dy_(dy) {}
    int size() const override { return inner_.size(); }
    Result<ReferenceInfo> info(int ref) override { return inner_.info(ref); }  // the stack's, unshifted
    Status prepare(const std::vector<int>& refs, const Roi& region) override { return inner_.prepare(refs, shift(region)); }
    Status read_tile(int ref, const Roi& tile, float* rgba) override { return inner_.read_tile(ref, shift(tile), rgba); }

private:
    Roi shift(const Roi& r) const { return {r.x0 + dx_, r.y0 + dy_, r.x1 + dx_, r.y1 + dy_}; }
    StackPixels& inner_;
    int dx_, dy_;
};

// out's pixel (x, y) (at scale s) = the mean of full's pixels (scale 1) in
// [x / s, (x + 1) / s) x [y / s, (y + 1) / s); 0 where there are none.
void reduce_into(const Image& full, const ImageView& out, double sx, double sy) {
    const Roi src = full.data_window();
    const Roi& target = out.window;
    const int nc = std::min(out.nchannels, full.nchannels());
    for (int y = target.y0; y < target.y1; ++y) {
        const int ya = std::max(src.y0, int(std::floor(y / sy + 1e-9))), yb = std::min(src.y1, int(std::ceil((y + 1) / sy - 1e-9)));
        for (int x = target.x0; x < target.x1; ++x) {
            const int xa = std::max(src.x0, int(std::floor(x / sx + 1e-9))), xb = std::min(src.x1, int(std::ceil((x + 1) / sx - 1e-9)));
            const int n = std::max(0, xb - xa) * std::max(0, yb - ya);
            for (int c = 0; c < nc; ++c) {
                double s = 0;
                for (int v = ya; v < yb; ++v)
                    for (int u = xa; u < xb; ++u) s += full.at(c, u, v);
                out.at(c, x, y) = n ? float(s / n) : 0.0f;
            }
        }
    }
}

Status check_target(const CompositeTarget& t, const CompositeOptions& options) {
    const int n = t.view.nchannels;
    if (!t.view.valid()) return Status::error("composite target: no memory", StatusCode::InvalidArgument);
    if (!(options.aovs ? n == 6 : n == 3 || n == 4))
        return Status::error("composite target: " + std::to_string(n) + " channels; needs R, G, B[, A]" +
                                 (options.aovs ? " and the AOVs stack.index, stack.deviation (6)" : " (3 or 4)"),
                             StatusCode::InvalidArgument);
    for (double s : {t.render_scale_x, t.render_scale_y})
        if (!(s > 0) || !std::isfinite(s))
            return Status::error("composite target: render scale must be > 0, got " + std::to_string(s),
                                 StatusCode::InvalidArgument);
    return Status::ok();
}

}  // namespace

Result<Image> composite(const FocalStack& stack, const FocusSource& focus, StackPixels& pixels,
                        const CompositeOptions& options, CompositeStats* stats, const Exec& exec) {
    CompositeStats unused;
    CompositeStats& S = stats ? *stats : unused;
    S = CompositeStats{};
    const auto t0 = clock::now();
    auto desired = desired_focus(stack, focus, pixels, nullptr, exec);
    if (!desired) return desired.status();
    S.desired_seconds = seconds_since(t0);

    auto index = stack_index(stack);
    if (!index) return index.status();
    const auto t1 = clock::now();
    auto sel = select_references(*index, *desired, options, exec);
    if (!sel) return sel.status();
    S.select_seconds = seconds_since(t1);
    S.used_references = sel->used_references();
    if (S.used_references.empty())
        return Status::error("no pixel selected any reference (desired near/far are all NaN?)");

    // The output's windows and metadata: those of the first used reference.
    const int first = S.used_references.front();
    auto info = pixels.info(first);
    if (!info) return info.status();
    if (Status st = check_reference_size(stack, first, *info, *desired); !st) return st;
    const Roi& dw = info->data_window;
    auto out = composite_stack(*sel, pixels, options, dw.x0, dw.y0, &S, exec);
    if (!out) return about(out.status(), kPixels);
    out->set_display_window(info->display_window);
    out->metadata = info->metadata;
    for (const char* a : {"focusDistance", "focus", "fNumber", "aperture"}) out->metadata.erase(a);
    return out;
}

Status composite(const FocalStack& stack, const FocusSource& focus, StackPixels& pixels, const CompositeTarget& target,
                 const CompositeOptions& options, CompositeStats* stats, const Exec& exec) {
    CompositeStats unused;
    CompositeStats& S = stats ? *stats : unused;
    S = CompositeStats{};
    if (Status st = check_target(target, options); !st) return st;
    const ImageView& view = target.view;
    for (int y = view.window.y0; y < view.window.y1; ++y)
        for (int x = view.window.x0; x < view.window.x1; ++x)
            for (int c = 0; c < view.nchannels; ++c) view.at(c, x, y) = 0.0f;
    if (view.window.empty()) return Status::ok();

    // The region at full resolution, on the references' grid.
    auto ref0 = pixels.info(0);
    if (!ref0) return ref0.status();
    const Roi grid = ref0->data_window;
    const double sx = target.render_scale_x, sy = target.render_scale_y;
    const bool full = sx == 1.0 && sy == 1.0;
    const Roi& v = view.window;
    const Roi region = intersect(full ? v
                                      : Roi{int(std::floor(v.x0 / sx)), int(std::floor(v.y0 / sy)),
                                            int(std::ceil(v.x1 / sx)), int(std::ceil(v.y1 / sy))},
                                 grid);
    if (region.empty()) return Status::ok();

    const auto t0 = clock::now();
    auto desired = desired_focus(stack, focus, pixels, &*ref0, exec);
    if (!desired) return desired.status();
    if (Status st = check_reference_size(stack, 0, *ref0, *desired); !st) return st;
    S.desired_seconds = seconds_since(t0);

    auto index = stack_index(stack);
    if (!index) return index.status();
    const auto t1 = clock::now();
    const Roi local{region.x0 - grid.x0, region.y0 - grid.y0, region.x1 - grid.x0, region.y1 - grid.y0};
    auto sel = select_references(*index, crop(*desired, local), options, exec);
    if (!sel) return sel.status();
    S.select_seconds = seconds_since(t1);
    S.used_references = sel->used_references();

    ShiftedPixels shifted(pixels, local.x0, local.y0);
    if (full) {
        Status st = detail::composite_tiles(*sel, shifted, options, detail::view_planes(view, region), &S, exec);
        return st ? st : about(st, kPixels);
    }
    auto whole = composite_stack(*sel, shifted, options, region.x0, region.y0, &S, exec);
    if (!whole) return about(whole.status(), kPixels);
    reduce_into(*whole, view, sx, sy);
    return Status::ok();
}

}  // namespace gdof

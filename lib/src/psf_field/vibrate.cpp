// vibrate_layers: the aperture sampled, the layers moved and composited with
// visibility per sample, the samples averaged (psf_field.h, docs/psf_field.md).
// Samples run in batches of a fixed size, each sample on its own buffers, and
// are summed in sample order: the same bits for any thread count.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "psf_field/vibrate_internal.h"

namespace gdof {

using namespace vibrate_detail;

namespace {

constexpr int kBatch = 2;              // samples in flight (fixed, so results ignore the thread count)
constexpr float kMinWeight = 1e-3f;    // splatted weight below which a layer has nothing at a pixel

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Enough samples that neighbouring ones land at most ~2.5 px apart at the
// largest displacement (the prefilter hides that spacing), 16 to 1024.
int automatic_samples(double max_displacement_px) {
    const double n = std::numbers::pi * std::pow(max_displacement_px / 2.5, 2.0);
    return int(std::clamp(std::ceil(n), 16.0, 1024.0));
}

// One sample's buffers.
struct Scratch {
    SplatPyramid pyramid;
    std::vector<float> layers;  // per layer R, G, B, A, Z over the output (depth-moving fields: all, else one)
    std::vector<float> rgba;    // the sample's composite, 4 planes over the output
    Scratch(const Roi& out, int levels, std::size_t nlayers, bool keep_layers)
        : pyramid(out, levels), layers((keep_layers ? nlayers : 1) * 5 * out.npixels()), rgba(4 * out.npixels()) {}
};

// The cat's eye (Aperture::cats_eye, `amount` > 0): towards the frame's
// corners the aperture is cut by a unit disc displaced outward by
// d = amount x (distance from the centre / half diagonal), as --bokeh draws it,
// and the cut shape is centred back on its source. A sample (u, v) of the
// uncut aperture is mapped onto that lens: across the cut (along the outward
// axis) scaled by 1 - d/2, along it by the lens's chord over the disc's at
// that place, so the samples stay in the same order and every source keeps
// all of them (its light is not lost, only its shape changes).
struct CatsEye {
    CatsEyeVignette vignette;
    CatsEye(double a, const Roi& frame) : vignette(a, frame) {}
    void map(double x, double y, double& u, double& v) const {
        const CatsEyeCut cut = vignette.at(x, y);
        if (!(cut.d > 0.0)) return;
        const double d = std::min(cut.d, 1.999);
        const double ex = cut.ex, ey = cut.ey;
        const double a = u * ex + v * ey, b = -u * ey + v * ex;
        const double a2 = a * (1.0 - 0.5 * d);
        const double disc_chord = std::sqrt(std::max(0.0, 1.0 - a * a));
        const double t = std::abs(a2) + 0.5 * d, lens_chord = std::sqrt(std::max(0.0, 1.0 - t * t));
        const double b2 = disc_chord > 1e-12 ? b * std::min(1.0, lens_chord / disc_chord) : 0.0;
        u = a2 * ex - b2 * ey;
        v = a2 * ey + b2 * ex;
    }
};

// Layer `s` moved for sample (u, v): splatted, resolved and normalised into
// five planes (R, G, B, A, Z) over the output; returns where anything landed
// (output-relative pixels; zero and NaN Z elsewhere).
Roi moved_layer(const Sources& s, const PsfField& field, const Roi& frame, double u0, double v0, const CatsEye& eye,
                SplatPyramid& p, int nw, float* out) {
    p.clear();
    const Roi R = s.region;
    const int W = R.width();
    float m[SplatPyramid::kChannels];
    for (int yy = 0; yy < R.height(); ++yy)
        for (int xx = 0; xx < W; ++xx) {
            const std::size_t i = std::size_t(yy) * std::size_t(W) + std::size_t(xx);
            const double x = R.x0 + xx + 0.5, y = R.y0 + yy + 0.5;
            const float z = s.z[i];
            const PsfPoint pt{x, y, std::isfinite(z) ? double(z) : 0.0, double(s.blur[i]),
                              nw > 0 ? &s.weights[i * std::size_t(nw)] : nullptr};
            double u = u0, v = v0;
            eye.map(x, y, u, v);
            const PsfDisplacement d = field.displace(pt, u, v, frame);
            const float a = s.a[i];
            m[0] = s.r[i];
            m[1] = s.g[i];
            m[2] = s.b[i];
            m[3] = a;
            m[4] = a > 0.0f && std::isfinite(z) ? a * float(double(z) + d.dz) : 0.0f;
            m[5] = 1.0f;
            p.splat(x + d.dx, y + d.dy, s.level[i], m);
        }
    Roi box;
    const float* c = p.resolve(box);
    const std::size_t P = p.window().npixels();
    const int W_out = p.window().width();
    std::fill(out, out + 4 * P, 0.0f);
    std::fill(out + 4 * P, out + 5 * P, std::numeric_limits<float>::quiet_NaN());
    for (int y = box.y0; y < box.y1; ++y)
        for (int x = box.x0; x < box.x1; ++x) {
            const std::size_t i = std::size_t(y) * std::size_t(W_out) + std::size_t(x);
            const float* q = c + i * SplatPyramid::kChannels;
            const float w = q[5];
            float z = std::numeric_limits<float>::quiet_NaN();
            if (w > kMinWeight) {
                for (int k = 0; k < 4; ++k) out[std::size_t(k) * P + i] = q[k] / w;
                if (q[3] > 0.0f) z = q[4] / q[3];
            }
            out[4 * P + i] = z;
        }
    return box;
}

// `still`: per layer, its moved planes when no source moves with the sample
// (made once), else empty.
void render_sample(const std::vector<Sources>& layers, const std::vector<std::vector<float>>& still,
                   const std::vector<Roi>& still_box,
                   const PsfField& field, const Roi& frame, const Roi& out, const ApertureSample& smp, const CatsEye& eye,
                   Scratch& sc) {
    const std::size_t P = out.npixels();
    const int nw = field.weight_count();
    const bool by_depth = field.moves_depth();
    std::fill(sc.rgba.begin(), sc.rgba.end(), 0.0f);
    float* o[4] = {sc.rgba.data(), sc.rgba.data() + P, sc.rgba.data() + 2 * P, sc.rgba.data() + 3 * P};
    const int nl = int(layers.size());
    std::vector<const float*> planes(static_cast<std::size_t>(nl), nullptr);
    for (int l = nl - 1; l >= 0; --l) {  // back to front
        const Sources& s = layers[std::size_t(l)];
        if (s.empty) continue;
        const float* v = still[std::size_t(l)].data();
        Roi box = still_box[std::size_t(l)];
        if (still[std::size_t(l)].empty()) {
            float* buf = sc.layers.data() + (by_depth ? std::size_t(l) * 5 * P : 0);
            box = moved_layer(s, field, frame, smp.u, smp.v, eye, sc.pyramid, nw, buf);
            v = buf;
        }
        if (by_depth) {
            planes[std::size_t(l)] = v;
            continue;
        }
        // Outside the box the layer is empty: `over` changes nothing.
        for (int y = box.y0; y < box.y1; ++y)
            for (int x = box.x0; x < box.x1; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(out.width()) + std::size_t(x);
                const float t = 1.0f - std::clamp(v[3 * P + i], 0.0f, 1.0f);  // v over what is behind
                for (int k = 0; k < 4; ++k) o[k][i] = v[std::size_t(k) * P + i] + t * o[k][i];
            }
    }
    if (!by_depth) return;
    // Depth moved: per pixel, the layers front to back in their moved depth.
    std::vector<std::pair<float, int>> order(static_cast<std::size_t>(nl));
    for (std::size_t i = 0; i < P; ++i) {
        int n = 0;
        for (int l = 0; l < nl; ++l) {
            const float* v = planes[std::size_t(l)];
            if (!v) continue;
            if (!(v[3 * P + i] > 0.0f) && v[i] == 0.0f && v[P + i] == 0.0f && v[2 * P + i] == 0.0f) continue;
            const float z = v[4 * P + i];
            order[std::size_t(n++)] = {std::isnan(z) ? std::numeric_limits<float>::infinity() : z, l};
        }
        std::sort(order.begin(), order.begin() + n);  // ties: the layer order
        float acc[4] = {0, 0, 0, 0}, t = 1.0f;
        for (int k = 0; k < n; ++k) {
            const float* v = planes[std::size_t(order[std::size_t(k)].second)];
            for (int c = 0; c < 4; ++c) acc[c] += t * v[std::size_t(c) * P + i];
            t *= 1.0f - std::clamp(v[3 * P + i], 0.0f, 1.0f);
        }
        for (int c = 0; c < 4; ++c) o[c][i] = acc[c];
    }
}

Status check_layers(const std::vector<VibrateLayer>& layers) {
    for (std::size_t i = 0; i < layers.size(); ++i) {
        const VibrateLayer& l = layers[i];
        const std::string where = "vibrate: layer " + std::to_string(i);
        if (!l.image) return Status::error(where + " has no image", StatusCode::InvalidArgument);
        if (l.rgba.r < 0 || l.rgba.g < 0 || l.rgba.b < 0)
            return Status::error(where + " has no R, G, B channels", StatusCode::InvalidArgument);
        for (int c : {l.rgba.r, l.rgba.g, l.rgba.b, l.rgba.a, l.z})
            if (c >= l.image->nchannels() || (c >= 0 && !l.image->plane(c) && !l.image->data_window().empty()))
                return Status::error(where + ": channel " + std::to_string(c) + " is not a float channel",
                                     StatusCode::InvalidArgument);
    }
    return Status::ok();
}

}  // namespace

Result<Image> vibrate_layers(const std::vector<VibrateLayer>& front_to_back, const PsfField& field, const Aperture& aperture,
                             const Camera& camera, const Roi& frame, const Roi& output, const VibrateOptions& options,
                             VibrateStats* stats, const Exec& exec) {
    VibrateStats local;
    VibrateStats& S = stats ? *stats : local;
    S = VibrateStats{};
    if (Status st = check_layers(front_to_back); !st) return st;
    if (options.samples < 0 || options.samples > 65536)
        return Status::error("vibrate: samples must be 0 (automatic) to 65536, got " + std::to_string(options.samples),
                             StatusCode::InvalidArgument, "samples");
    if (!(options.prefilter >= 0.0) || options.prefilter > 10.0)
        return Status::error("vibrate: prefilter must be in [0, 10]", StatusCode::InvalidArgument, "prefilter");
    if (Status st = validate(aperture); !st) return st.prefix("vibrate");
    Image result = Image::with_channels({"R", "G", "B", "A"}, output);
    if (output.empty()) return result;

    auto t0 = std::chrono::steady_clock::now();
    std::vector<Sources> layers;
    for (const VibrateLayer& l : front_to_back) {
        auto s = prepare_sources(l, field, camera, frame, output, exec);
        if (!s) return s.status();
        S.max_displacement_px = std::max(S.max_displacement_px, s->max_displacement);
        layers.push_back(std::move(s).value());
    }
    const int n = options.samples > 0 ? options.samples
                  : field.samples() > 0 ? field.samples()
                                        : automatic_samples(S.max_displacement_px);
    // The samples of the uncut aperture; the cat's eye maps them per source.
    double spacing = 0.0;
    Aperture uncut = aperture;
    uncut.cats_eye = 0.0;
    const CatsEye eye(aperture.cats_eye, frame);
    auto samples = aperture_samples(uncut, n, options.seed, &spacing);
    if (!samples) return samples.status().prefix("vibrate");
    for (Sources& s : layers) set_levels(s, spacing, options.prefilter);
    const int levels = levels_needed(layers);
    S.samples = int(samples->size());
    S.spacing = spacing;
    for (const Sources& s : layers)
        if (!s.empty) S.splats += s.region.npixels() * (s.still ? 1 : samples->size());
    S.t_prepare = seconds_since(t0);

    t0 = std::chrono::steady_clock::now();
    const std::size_t P = output.npixels();
    // Layers that no sample moves: made once (in parallel over layers; each
    // on its own pyramid).
    std::vector<std::vector<float>> still(layers.size());
    std::vector<Roi> still_box(layers.size());
    std::vector<int> still_index;
    for (std::size_t l = 0; l < layers.size(); ++l)
        if (!layers[l].empty && layers[l].still) still_index.push_back(int(l));
    if (Status st = parallel_run(exec, long(still_index.size()), [&](long i0, long i1) {
            SplatPyramid p(output, levels);
            for (long i = i0; i < i1; ++i) {
                const std::size_t l = std::size_t(still_index[std::size_t(i)]);
                still[l].resize(5 * P);
                still_box[l] = moved_layer(layers[l], field, frame, 0.0, 0.0, CatsEye(0.0, frame), p, field.weight_count(),
                                           still[l].data());
            }
            return Status::ok();
        }, 1, "vibrate");
        !st)
        return st;
    std::vector<double> acc(4 * P, 0.0);
    std::vector<std::unique_ptr<Scratch>> scratch;
    const long ns = long(samples->size());
    for (long b0 = 0; b0 < ns; b0 += kBatch) {
        const long b1 = std::min(ns, b0 + kBatch);
        while (long(scratch.size()) < b1 - b0)
            scratch.push_back(std::make_unique<Scratch>(output, levels, layers.size(), field.moves_depth()));
        Status st = parallel_run(exec, b1 - b0, [&](long i0, long i1) {
            for (long i = i0; i < i1; ++i)
                render_sample(layers, still, still_box, field, frame, output, (*samples)[std::size_t(b0 + i)], eye,
                              *scratch[std::size_t(i)]);
            return Status::ok();
        }, 1, "vibrate");
        if (!st) return st;
        for (long i = 0; i < b1 - b0; ++i) {  // in sample order
            const float* r = scratch[std::size_t(i)]->rgba.data();
            for (std::size_t k = 0; k < 4 * P; ++k) acc[k] += double(r[k]);
        }
        exec.report(double(b1) / double(ns));
    }
    for (int c = 0; c < 4; ++c) {
        float* dst = result.plane(c);
        for (std::size_t i = 0; i < P; ++i) dst[i] = float(acc[std::size_t(c) * P + i] / double(ns));
    }
    S.t_render = seconds_since(t0);
    return result;
}

}  // namespace gdof

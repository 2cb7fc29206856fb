// prepare_plate_depth (plate.h): decode, remove speckles, fill holes, give
// mixed silhouette pixels the nearer surface's depth, decide the holes at
// silhouettes by their colour, count what was done.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "common/format_number.h"
#include "plate/plate_internal.h"

namespace gdof {

using namespace plate_detail;

std::string DepthCleanupStats::report() const {
    auto pct = [&](std::size_t v) {
        char b[32];
        std::snprintf(b, sizeof b, "%.1f%%", pixels ? 100.0 * double(v) / double(pixels) : 0.0);
        return std::string(b);
    };
    char noise_text[32];
    std::snprintf(noise_text, sizeof noise_text, "%.2f%%", 100.0 * noise);
    const std::string window =
        std::to_string(2 * noise_smoothing_radius + 1) + "x" + std::to_string(2 * noise_smoothing_radius + 1);
    return "depth: " + std::to_string(holes) + " holes (" + pct(holes) + "), " + std::to_string(speckles) +
           " speckle pixels, " + std::to_string(filled) + " filled (" + std::to_string(silhouette_holes) +
           " at silhouettes by colour), " + std::to_string(mixed) +
           " mixed silhouette pixels to the nearer surface" +
           (sharp_fronts ? " (" + std::to_string(sharp_fronts) + " split where the front is sharper)" : std::string()) +
           ", " + std::to_string(sky) + " sky (" + pct(sky) + "), noise " +
           noise_text + (noise_smoothing_radius > 0 ? " (smoothed " + window + ")" : "");
}

namespace {

constexpr float kInfF = std::numeric_limits<float>::infinity();

// A plate whose every finite depth lies within the camera's focal length
// shows nothing a lens could focus on: almost always an integer depth file
// read as 0..1 and decoded as scene units (millimetres at scale 0.001), which
// would otherwise defocus the whole frame at the largest blur, silently.
// Unknown focal length (a camera from matrices alone): not checked.
Status check_depth_beyond_focal_length(float nearest, float farthest, const std::string& channel, const Camera& camera) {
    const double focal = focal_length_scene_units(camera);
    if (!(focal > 0.0) || !std::isfinite(focal) || !(farthest >= nearest) || double(farthest) > focal) return Status::ok();
    return Status::error("plate depth: every depth of channel '" + channel + "' decodes within the camera's focal length (" +
                             format_number(nearest, 6) + " to " + format_number(farthest, 6) + " scene units; focal length " +
                             format_number(focal, 6) + "), where no lens can focus: " + kDepthScaleHint,
                         StatusCode::InvalidArgument, "depth_scale");
}

// prepare_plate_depth with or without a camera (nullptr).
Result<PlateDepth> prepare(const Image& plate, int depth_channel, const DepthDecode& decode, const Camera* camera,
                           const DepthCleanupOptions& options, const Exec& exec) {
    if (depth_channel < 0 || depth_channel >= plate.nchannels())
        return Status::error("plate depth: channel index " + std::to_string(depth_channel) + " out of range",
                             StatusCode::InvalidArgument, "depth_channel");
    if (plate.channel(depth_channel).type == PixelType::UInt)
        return Status::error("plate depth: channel '" + plate.channel(depth_channel).name + "' is not a float channel",
                             StatusCode::InvalidArgument, "depth_channel");
    if (!(options.continuity > 1.0) || !(options.continuity < 2.0))
        return Status::error("plate depth: continuity must be in (1, 2), got " + std::to_string(options.continuity),
                             StatusCode::InvalidArgument, "continuity");
    if (!(options.mixed_step >= options.continuity) || !(options.mixed_step < 100.0))
        return Status::error("plate depth: mixed_step must be in [continuity, 100), got " +
                                 std::to_string(options.mixed_step),
                             StatusCode::InvalidArgument, "mixed_step");
    if (options.speckle_px < 0 || options.speckle_px > 100000)
        return Status::error("plate depth: speckle_px must be in 0..100000, got " + std::to_string(options.speckle_px),
                             StatusCode::InvalidArgument, "speckle_px");
    if (!camera && (decode.range || (decode.encoding == DepthEncoding::Disparity && !std::isnan(decode.baseline))))
        return Status::error("depth channel '" + plate.channel(depth_channel).name + "': " +
                                 (decode.range ? "a distance along the ray" : "a disparity from a baseline") +
                                 " needs a camera to decode (a focal length)",
                             StatusCode::InvalidArgument, "focal_length_mm");
    // Without a camera nothing below reads one: the decode needs none.
    Result<DepthDecode> dec = decode;
    if (camera) dec = resolve_depth_decode(decode, *camera);
    else if (Status st = decode.validate(); !st) dec = st;
    if (!dec) return dec.status().prefix("depth channel '" + plate.channel(depth_channel).name + "'");

    PlateDepth out;
    const Roi win = plate.data_window();
    out.window = win;
    const int W = win.width(), H = win.height();
    const std::size_t n = plate.npixels();
    out.depth.resize(n);
    out.stats.pixels = n;
    const float* raw = plate.plane(depth_channel);
    std::vector<std::size_t> row_holes(std::size_t(H), 0);
    std::vector<float> row_near(std::size_t(H), kInfF), row_far(std::size_t(H), -kInfF);  // finite depths' range
    parallel_for(exec, H, [&](long r0, long r1) {
        for (int y = int(r0); y < int(r1); ++y)
            for (int x = 0; x < W; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
                double z = decode_depth(raw[i], *dec);
                if (dec->range && std::isfinite(z))
                    z /= length(camera->depth_line(win.x0 + x + 0.5, win.y0 + y + 0.5).per_depth);
                out.depth[i] = float(z);
                if (std::isnan(z)) ++row_holes[std::size_t(y)];
                if (std::isfinite(out.depth[i])) {
                    row_near[std::size_t(y)] = std::min(row_near[std::size_t(y)], out.depth[i]);
                    row_far[std::size_t(y)] = std::max(row_far[std::size_t(y)], out.depth[i]);
                }
            }
    }, 16);
    for (std::size_t h : row_holes) out.stats.holes += h;
    if (n == 0) return out;
    if (camera)
        if (Status st = check_depth_beyond_focal_length(*std::min_element(row_near.begin(), row_near.end()),
                                                        *std::max_element(row_far.begin(), row_far.end()),
                                                        plate.channel(depth_channel).name, *camera);
            !st)
            return st;
    if (out.stats.holes == n)
        return Status::error("plate depth: channel '" + plate.channel(depth_channel).name +
                                 "' has no valid depth (every value is invalid under the " + to_string(dec->encoding) +
                                 " encoding)",
                             StatusCode::InvalidArgument, "depth_encoding");
    if (exec.is_cancelled()) return Status::cancelled("plate depth");

    // Each step's parallel loops stop at a cancel and leave their output
    // unfinished: the next step must not run on it (the checks below).
    // Silhouette pixels between two surfaces are found first: they are small
    // islands too, but not speckles.
    const std::vector<unsigned char> mixed = mixed_candidates(out.depth, W, H, options.continuity, exec);
    if (exec.is_cancelled()) return Status::cancelled("plate depth");
    // Noise is measured on what the sensor gave (holes and speckles do not
    // count: they are not within a surface).
    out.stats.noise = estimate_depth_noise(out.depth, W, H, options.continuity, exec);
    if (exec.is_cancelled()) return Status::cancelled("plate depth");
    if (options.remove_speckles) {
        const int max_px = options.speckle_px > 0 ? options.speckle_px : int(std::max<std::size_t>(4, n / 250000));
        out.stats.speckles = remove_speckles(out.depth, W, H, options.continuity, max_px, mixed, exec);
        if (exec.is_cancelled()) return Status::cancelled("plate depth");
    }
    // The colour guide (three planes the plate's size) only when there is a
    // hole to fill: most rendered depth has none.
    const bool any_hole = out.stats.holes + out.stats.speckles > 0;
    std::vector<unsigned char> was_hole;
    if (any_hole && options.mixed_pixels) {
        was_hole.resize(n);
        for (std::size_t i = 0; i < n; ++i) was_hole[i] = std::isnan(out.depth[i]) ? 1 : 0;
    }
    if (any_hole)
        if (Status st = fill_holes(out.depth, W, H, make_guide(plate, exec), exec, out.stats.filled); !st)
            return st.prefix("plate depth");
    if (options.smooth_noise && out.stats.noise > kNoisyDepth) {
        out.stats.noise_smoothing_radius = kNoiseSmoothingRadius;
        smooth_depth_noise(out.depth, W, H, options.continuity, kNoiseSmoothingRadius, mixed, exec);
        if (exec.is_cancelled()) return Status::cancelled("plate depth");
    }
    if (options.mixed_pixels) {
        std::vector<MixedStep> steps;
        out.stats.mixed = mixed_to_nearer(out.depth, W, H, options.mixed_step, exec, &steps);
        if (exec.is_cancelled()) return Status::cancelled("plate depth");
        const RgbaIndices ix = find_rgba(plate);
        const float* rgb[3] = {ix.r >= 0 ? plate.plane(ix.r) : nullptr, ix.g >= 0 ? plate.plane(ix.g) : nullptr,
                               ix.b >= 0 ? plate.plane(ix.b) : nullptr};
        if (!was_hole.empty()) {  // the colour decides only holes
            out.mixed = split_silhouette_holes(out.depth, was_hole, mixed, W, H, options.continuity, options.mixed_step,
                                               rgb, out.stats.silhouette_holes);
            // A filled hole is decided by step 5 alone.
            std::erase_if(steps, [&](const MixedStep& m) { return was_hole[m.index] != 0; });
        }
        out.front_mixed = front_parts(out.depth, steps, was_hole, W, H, options.continuity, rgb,
                                      ix.a >= 0 ? plate.plane(ix.a) : nullptr);
    }
    for (float d : out.depth)
        if (std::isinf(d)) ++out.stats.sky;
    return out;
}

}  // namespace

Result<PlateDepth> prepare_plate_depth(const Image& plate, int depth_channel, const DepthDecode& decode,
                                       const Camera& camera, const DepthCleanupOptions& options, const Exec& exec) {
    return prepare(plate, depth_channel, decode, &camera, options, exec);
}

Result<PlateDepth> prepare_plate_depth(const Image& plate, int depth_channel, const DepthDecode& decode,
                                       const DepthCleanupOptions& options, const Exec& exec) {
    return prepare(plate, depth_channel, decode, nullptr, options, exec);
}

namespace {
// Entry `index` of a list by increasing index, or nullptr.
const MixedPixel* find_pixel(const std::vector<MixedPixel>& list, std::size_t index) {
    auto it = std::lower_bound(list.begin(), list.end(), index,
                               [](const MixedPixel& m, std::size_t i) { return m.index < i; });
    return it != list.end() && it->index == index ? &*it : nullptr;
}
}  // namespace

const MixedPixel* PlateDepth::mixed_at(std::size_t index) const { return find_pixel(mixed, index); }

const MixedPixel* PlateDepth::front_mixed_at(std::size_t index) const { return find_pixel(front_mixed, index); }

}  // namespace gdof

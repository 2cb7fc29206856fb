#include "gdof/blur_map.h"

#include <atomic>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include "gdof/image_ops.h"
#include "image/row_major_planes.h"
#include "image/view_shape.h"

namespace gdof {

namespace {

// Three float channels layer.{x,y,z} (or X/Y/Z, R/G/B, r/g/b, red/green/blue).
std::optional<std::array<int, 3>> find_xyz(const Image& img, const std::string& layer) {
    static const char* const kSets[][3] = {
        {"x", "y", "z"}, {"X", "Y", "Z"}, {"R", "G", "B"}, {"r", "g", "b"}, {"red", "green", "blue"}};
    for (const auto& set : kSets) {
        std::array<int, 3> idx{};
        bool ok = true;
        for (int k = 0; k < 3 && ok; ++k) {
            idx[std::size_t(k)] = img.channel_index(layer + "." + set[k]);
            ok = idx[std::size_t(k)] >= 0 && img.channel(idx[std::size_t(k)]).type != PixelType::UInt;
        }
        if (ok) return idx;
    }
    return std::nullopt;
}

// Runs row(y) over the rows in parallel (parallel_run: the error returned is
// that of the lowest failing row, whatever the thread count); progress per row.
Status for_rows(const Exec& exec, int height, const std::function<Status(long)>& row) {
    std::atomic<long> done{0};
    return parallel_run(exec, height, [&](long y0, long y1) -> Status {
        for (long y = y0; y < y1; ++y) {
            if (Status st = row(y); !st) return st;
            exec.report(double(++done) / double(height));
        }
        return Status::ok();
    });
}

}  // namespace

Result<std::optional<std::array<int, 3>>> find_position_channels(const Image& img, const std::string& spec) {
    using R = std::optional<std::array<int, 3>>;
    if (spec.find(',') != std::string::npos) {
        auto names = split_list(spec);
        if (!names || names->size() != 3)
            return Status::error("position channels '" + spec + "': expected a layer name or three channel names x,y,z");
        std::array<int, 3> idx{};
        for (int k = 0; k < 3; ++k) {
            const std::string& n = (*names)[std::size_t(k)];
            idx[std::size_t(k)] = img.channel_index(n);
            if (idx[std::size_t(k)] < 0) return Status::error("position channel '" + n + "' not found");
            if (img.channel(idx[std::size_t(k)]).type == PixelType::UInt)
                return Status::error("position channel '" + n + "' is not a float channel");
        }
        return R(idx);
    }
    if (!spec.empty()) {
        auto idx = find_xyz(img, spec);
        if (!idx)
            return Status::error("no position channels " + spec + ".x/" + spec + ".y/" + spec +
                                 ".z (or .X/.Y/.Z, .R/.G/.B, .red/.green/.blue)");
        return R(idx);
    }
    for (const char* layer : {"P", "Pworld", "p", "position", "Position"})
        if (auto idx = find_xyz(img, layer)) return R(idx);
    return R(std::nullopt);
}

Result<int> find_depth_channel(const Image& img, const std::string& name) {
    if (!name.empty()) {
        int c = img.channel_index(name);
        if (c < 0) return Status::error("depth channel '" + name + "' not found", StatusCode::NotFound, "depth_channel");
        if (img.channel(c).type == PixelType::UInt)
            return Status::error("depth channel '" + name + "' is not a float channel", StatusCode::InvalidArgument,
                                 "depth_channel");
        return c;
    }
    for (const char* n : {"Z", "depth.Z", "Depth.Z", "depth", "Depth"}) {
        int c = img.channel_index(n);
        if (c >= 0 && img.channel(c).type != PixelType::UInt) return c;
    }
    return -1;
}

// evaluate_blur_map into a row-major plane over the data window.
static Status blur_map_into(const BlurField& field, const Camera& camera, const Image& img, const PositionSource& source,
                            float* out, const Exec& exec) {
    auto pos = find_position_channels(img, source.position_channels);
    if (!pos) return pos.status();
    int zc = -1;
    if (!*pos) {
        auto z = find_depth_channel(img, source.depth_channel);
        if (!z) return z.status();
        zc = *z;
        if (zc < 0)
            return Status::error("no position channels (P.x/P.y/P.z, P.X/Y/Z, P.R/G/B, P.red/green/blue, Pworld.*) "
                                 "and no depth channel '" +
                                 (source.depth_channel.empty() ? std::string("Z") : source.depth_channel) + "'");
    } else if (auto z = find_depth_channel(img, source.depth_channel); z && *z >= 0 && source.depth_decode.validate()) {
        // With positions, the depth channel (when there is a usable one)
        // stands in for sky pixels: P not finite and depth +inf. A render's
        // sky has A = 1 under a lit environment but P = NaN (no hit) and
        // Z = +inf, and B must accept the sky (layers.h) instead of turning
        // NaN. A NaN P at a finite depth stays NaN (a broken position pass
        // is reported by the caller, not papered over).
        zc = *z;
    }
    if (zc >= 0 && !*pos) {
        if (Status st = source.depth_decode.validate(); !st) return st.prefix("depth channel '" + img.channel(zc).name + "'");
    }
    const Roi win = img.data_window();
    const int width = win.width();
    if (win.empty()) return Status::ok();
    const float* px = *pos ? img.plane((**pos)[0]) : nullptr;
    const float* py = *pos ? img.plane((**pos)[1]) : nullptr;
    const float* pz = *pos ? img.plane((**pos)[2]) : nullptr;
    const float* zp = zc >= 0 ? img.plane(zc) : nullptr;
    return for_rows(exec, win.height(), [&](long row) -> Status {
        const std::size_t off = std::size_t(row) * std::size_t(width);
        std::span<float> dst(out + off, std::size_t(width));
        const double yc = double(win.y0 + row) + 0.5;
        auto from_depth = [&](int i) {
            return PixelDepth{double(win.x0 + i) + 0.5, yc, decode_depth(double(zp[off + std::size_t(i)]), source.depth_decode)};
        };
        if (px) {
            std::vector<Vec3> points(static_cast<std::size_t>(width));
            for (int i = 0; i < width; ++i)
                points[std::size_t(i)] = Vec3(px[off + std::size_t(i)], py[off + std::size_t(i)], pz[off + std::size_t(i)]);
            if (Status st = field.evaluate(camera, std::span<const Vec3>(points), dst); !st) return st;
            if (!zp) return Status::ok();
            for (int i = 0; i < width; ++i) {
                const Vec3& p = points[std::size_t(i)];
                if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) continue;
                const PixelDepth s = from_depth(i);
                if (s.depth != std::numeric_limits<double>::infinity()) continue;
                if (Status st = field.evaluate(camera, std::span<const PixelDepth>(&s, 1), dst.subspan(std::size_t(i), 1)); !st)
                    return st;
            }
            return Status::ok();
        }
        std::vector<PixelDepth> samples(static_cast<std::size_t>(width));
        for (int i = 0; i < width; ++i) samples[std::size_t(i)] = from_depth(i);
        return field.evaluate(camera, std::span<const PixelDepth>(samples), dst);
    });
}

// evaluate_blur_deep into total_samples() floats.
static Status blur_deep_into(const BlurField& field, const Camera& camera, const DeepImage& img, int z_channel, float* out,
                             const Exec& exec) {
    const int zc = z_channel >= 0 ? z_channel : img.z_channel();
    if (zc < 0 || zc >= img.nchannels() || img.channel(zc).type == PixelType::UInt)
        return Status::error("deep image has no float depth channel 'Z'");
    const Roi win = img.data_window();
    const int width = win.width();
    if (win.empty() || img.total_samples() == 0) return Status::ok();
    const float* z = img.samples(zc);
    return for_rows(exec, win.height(), [&](long row) -> Status {
        const std::size_t p0 = img.pixel_index(win.x0, win.y0 + int(row));
        const std::size_t pl = p0 + std::size_t(width) - 1;
        const std::size_t first = img.first_sample(p0), last = img.first_sample(pl) + img.sample_count(pl);
        if (last == first) return Status::ok();
        std::vector<PixelDepth> samples;
        samples.reserve(last - first);
        for (int i = 0; i < width; ++i) {
            const std::size_t p = p0 + std::size_t(i);
            for (std::size_t k = img.first_sample(p); k < img.first_sample(p) + img.sample_count(p); ++k)
                samples.push_back({double(win.x0 + i) + 0.5, double(win.y0 + row) + 0.5, double(z[k])});
        }
        return field.evaluate(camera, std::span<const PixelDepth>(samples), std::span<float>(out + first, last - first));
    });
}

Status evaluate_blur_map(const BlurField& field, const Camera& camera, const Image& img, const PositionSource& source,
                         const ImageView& out, const Exec& exec) {
    if (Status st = image_detail::check_view_shape(out, 1, img.data_window(), "blur map output"); !st) return st;
    const image_detail::RowMajorPlanes<float> plane(out);
    Status st = blur_map_into(field, camera, img, source, img.data_window().empty() ? nullptr : plane.plane(0), exec);
    plane.store();
    return st;
}

Status evaluate_blur_deep(const BlurField& field, const Camera& camera, const DeepImage& img, int z_channel,
                          std::span<float> out, const Exec& exec) {
    if (out.size() != img.total_samples())
        return Status::error("deep blur output has " + std::to_string(out.size()) + " values; expected one per sample (" +
                                 std::to_string(img.total_samples()) + ")",
                             StatusCode::InvalidArgument);
    return blur_deep_into(field, camera, img, z_channel, out.data(), exec);
}

}  // namespace gdof

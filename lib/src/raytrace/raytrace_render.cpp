// The render loop: the display window in tiles, in parallel; each pixel's
// samples (sample_pixel.h) written to the flat image or the deep surfaces.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>

#include "common/flush_denormals.h"
#include "raytrace/render_setup.h"
#include "raytrace/sample_pixel.h"

namespace gdof {

namespace {

// Where the pixels go: the flat image (beauty + AOVs) or each pixel's deep
// surfaces (assembled into the deep image at the end).
struct RenderOutputs {
    Image* flat = nullptr;
    rt::FlatLayout layout;
    bool deep = false;
    std::vector<std::vector<rt::DeepSurface>> deep_pixels;  // row-major over the window
    Roi window;
    Vec3 environment;
    bool env_opaque = false;  // a visible (non-black) environment is part of the picture: alpha 1
    bool want_id = false;

    // `samples` is reordered for the deep surfaces.
    void write(const rt::PixelContext& ctx, int x, int y, std::vector<rt::Sample>& samples,
               rt::RenderCounters& counters) {
        if (flat) {
            const std::uint32_t id = want_id ? rt::central_object_id(ctx, x, y, samples, counters) : 0;
            rt::write_flat_pixel(*flat, layout, flat->offset(x, y), samples, id, env_opaque);
        }
        if (deep) {
            const std::size_t pix =
                std::size_t(y - window.y0) * std::size_t(window.width()) + std::size_t(x - window.x0);
            rt::deep_pixel(samples, environment, env_opaque, deep_pixels[pix]);
        }
    }
};

RenderOutputs make_outputs(const Scene& scene, const Camera& camera, const RenderOptions& options,
                           const std::string& label, Image* flat, bool deep) {
    RenderOutputs out;
    out.window = camera.display_window();
    out.environment = scene.environment;
    out.env_opaque = scene.environment.x > 0 || scene.environment.y > 0 || scene.environment.z > 0;
    out.want_id = has(options.aovs, RenderAov::Id);
    if (flat) {
        std::vector<ChannelSpec> specs;
        out.layout = rt::FlatLayout::make(options.aovs, specs);
        *flat = Image(specs, out.window, out.window);
        camera.to_metadata(flat->metadata);
        flat->metadata.set_string("gdof:renderCamera", label);
        out.flat = flat;
    }
    out.deep = deep;
    if (deep) out.deep_pixels.resize(out.window.npixels());
    return out;
}

Status render_tile(const rt::PixelContext& ctx, const Roi& tile, RenderOutputs& out, rt::PixelScratch& scratch,
                   rt::RenderCounters& counters) {
    for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; ++x) {
            if (Status st = rt::sample_pixel(ctx, x, y, scratch, counters); !st) return st;
            out.write(ctx, x, y, scratch.samples, counters);
        }
    return {};
}

struct AtomicCounters {
    std::atomic<std::uint64_t> primary{0}, segments{0}, shadow{0}, id{0};
    void add(const rt::RenderCounters& c) { primary += c.primary, segments += c.segments, shadow += c.shadow, id += c.id; }
};

// Renders into a flat image or (deep != nullptr) per-pixel deep surfaces.
Status render_impl(const RayTracer& tracer, const RenderOptions& settings, RenderStats* stats, const Exec& exec,
                   Image* flat, DeepImage* deep) {
    const Scene& scene = tracer.scene();
    Camera cam = scene.camera;
    if (settings.lens) cam.set_lens(*settings.lens);
    if (Status st = rt::check_render_options(settings); !st) return st;
    auto setup_r = rt::make_render_setup(scene, cam, settings);
    if (!setup_r) return setup_r.status();
    const rt::RenderSetup& setup = setup_r.value();

    RenderOutputs out = make_outputs(scene, cam, settings, setup.label, flat, deep != nullptr);
    const rt::LightSampler lights(scene);
    const bool jitter = settings.pixel_jitter && settings.spp > 1;
    const rt::PixelContext ctx{tracer,
                               setup.camera,
                               lights,
                               settings,
                               std::min(settings.min_spp, settings.spp),
                               jitter,
                               setup.camera.kind() == RenderCamera::Kind::Pinhole && !jitter};
    const TileGrid grid(out.window, settings.tile_size);
    AtomicCounters totals;
    std::atomic<long> tiles_done{0};
    const auto t0 = std::chrono::steady_clock::now();

    // parallel_run: the error of the lowest failing tile, whatever the thread count.
    Status st = parallel_run(
        exec, grid.count(),
        [&](long tb, long te) {
            const ScopedFlushDenormals ftz;
            rt::PixelScratch scratch;
            for (long t = tb; t < te; ++t) {
                if (exec.is_cancelled()) return Status::ok();  // parallel_run reports "render cancelled"
                rt::RenderCounters c;
                if (Status ts = render_tile(ctx, grid.tile(t), out, scratch, c); !ts) return ts;
                totals.add(c);
                exec.report(double(++tiles_done) / double(grid.count()));
            }
            return Status::ok();
        },
        1, "render");
    if (!st) return st;
    if (stats) {
        stats->primary_rays = totals.primary;
        stats->segments = totals.segments;
        stats->shadow_rays = totals.shadow;
        stats->id_rays = totals.id;
        stats->sample_cap = std::uint64_t(out.window.npixels()) * std::uint64_t(settings.spp);
        stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        stats->camera = setup.label;
    }
    if (deep) {
        auto made = rt::make_deep_image(out.window, settings.aovs, out.deep_pixels);
        if (!made) return made.status();
        *deep = std::move(made).value();
        cam.to_metadata(deep->metadata);
        deep->metadata.set_string("gdof:renderCamera", setup.label);
    }
    return {};
}

}  // namespace

Result<Image> render(const Scene& scene, const RenderOptions& settings, RenderStats* stats, const Exec& exec) {
    auto rt = RayTracer::build(scene);
    if (!rt) return rt.status();
    return render(*rt.value(), settings, stats, exec);
}

Result<Image> render(const RayTracer& tracer, const RenderOptions& settings, RenderStats* stats,
                     const Exec& exec) {
    Image img;
    Status st = render_impl(tracer, settings, stats, exec, &img, nullptr);
    if (!st) return st;
    return img;
}

Result<DeepImage> render_deep(const RayTracer& tracer, const RenderOptions& settings, RenderStats* stats,
                              const Exec& exec) {
    DeepImage deep;
    Status st = render_impl(tracer, settings, stats, exec, nullptr, &deep);
    if (!st) return st;
    return deep;
}

std::string RenderStats::report() const {
    char buf[1024];
    std::snprintf(buf, sizeof buf,
                  "  camera            %s\n"
                  "  primary rays      %llu (%.1f%% of the %llu-sample cap; adaptive saved %.1f%%)\n"
                  "  segments          %llu (%.3f per ray)\n"
                  "  shadow rays       %llu (+ %llu central rays for the id channel)\n"
                  "  time              %.3f s, %.2f Mrays/s (all rays and segments)\n",
                  camera.c_str(), (unsigned long long)primary_rays,
                  sample_cap ? 100.0 * double(primary_rays) / double(sample_cap) : 0.0,
                  (unsigned long long)sample_cap, 100.0 * adaptive_savings(), (unsigned long long)segments,
                  segments_per_ray(), (unsigned long long)shadow_rays, (unsigned long long)id_rays, seconds, mrays_per_second());
    return buf;
}

}  // namespace gdof

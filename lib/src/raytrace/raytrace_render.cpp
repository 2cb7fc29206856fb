// The render loop: tiles in parallel, per-pixel seeded aperture samples
// (pinhole, straight thin lens, or polyline rays of a blur field), adaptive
// sample counts, AOVs averaged over the samples.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <mutex>
#include <optional>

#include "common/flush_denormals.h"
#include "gdof/lens_rays.h"
#include "raytrace/raytrace_internal.h"

namespace gdof {

namespace {

enum class Mode { Pinhole, StraightThinLens, Polyline };

struct Setup {
    Mode mode = Mode::Pinhole;
    std::optional<NonlinearCamera> ncam;
    double lens_radius = 0, focus_depth = 0;  // StraightThinLens
    std::string label;
};

Result<Setup> make_setup(const Scene& scene, const Camera& camera, const RenderOptions& s) {
    Setup st;
    if (s.pinhole) {
        st.label = "pinhole";
        return st;
    }
    std::optional<BlurField> field;
    if (s.blur_field) {
        field = *s.blur_field;
        st.label = "blur field " + field->describe();
    } else if (std::isfinite(camera.lens().f_number) && std::isfinite(camera.lens().focus_distance)) {
        auto lens = camera.thin_lens();
        if (!lens) return Status::error("camera: " + lens.message());
        if (s.straight_thin_lens) {
            st.mode = Mode::StraightThinLens;
            st.lens_radius = thin_lens_equivalent_radius(lens.value());
            st.focus_depth = lens->focus_distance;
            st.label = "thin lens (straight rays)";
            return st;
        }
        auto f = BlurField::from_thin_lens(lens.value());
        if (!f) return f.status();
        field = f.value();
        st.label = "thin lens (polyline rays)";
    } else {
        st.label = "pinhole (the scene camera has no f_number / focus_distance)";
        return st;
    }
    // Sample B only over the depths the scene occupies (beyond, the last
    // segment runs straight on): much cheaper than the default range.
    NonlinearCameraOptions opts;
    opts.profile_tolerance_px = s.polyline_tolerance_px;
    opts.ray_tolerance_px = s.polyline_tolerance_px;
    double dmin = std::numeric_limits<double>::infinity(), dmax = 0;
    for (const TriangleMesh& m : scene.meshes)
        for (std::size_t v = 0; v < m.vertex_count(); ++v) {
            const double d = camera.project(m.vertex(v)).depth;
            if (d > 0) dmin = std::min(dmin, d), dmax = std::max(dmax, d);
        }
    if (dmax > 0) {
        opts.depth_min = std::max(opts.depth_min, 0.5 * dmin);
        opts.depth_max = std::max(opts.depth_min * 2, 1.01 * dmax);
    }
    auto nc = NonlinearCamera::create(camera, *field, opts);
    if (!nc) return Status::error("camera: " + nc.message());
    st.ncam = std::move(nc).value();
    st.mode = Mode::Polyline;
    return st;
}

struct TileCounters {
    std::uint64_t primary = 0, segments = 0, shadow = 0, id = 0;
};

// Welford running variance of the samples' luminance (the adaptive stop).
struct LuminanceStats {
    int n = 0;
    double mean = 0, m2 = 0;
    void add(double l) {
        ++n;
        const double d = l - mean;
        mean += d / n;
        m2 += d * (l - mean);
    }
    bool converged(double threshold) const {
        if (threshold <= 0 || n < 2) return false;
        const double se = std::sqrt(m2 / (n - 1) / n);
        return se <= threshold * std::max(mean, 0.01);
    }
};

// Renders into a flat image or (deep != nullptr) per-pixel deep surfaces.
Status render_impl(const RayTracer& tracer, const RenderOptions& settings, RenderStats* stats, const Exec& exec,
                   Image* flat, DeepImage* deep) {
    const Scene& scene = tracer.scene();
    Camera cam = scene.camera;
    if (settings.lens) cam.set_lens(*settings.lens);
    if (settings.spp < 1) return Status::error("spp: must be >= 1, got " + std::to_string(settings.spp));
    if (settings.min_spp < 1) return Status::error("min_spp: must be >= 1, got " + std::to_string(settings.min_spp));
    if (settings.tile_size < 1) return Status::error("tile_size: must be >= 1");
    if (!(settings.adaptive_threshold >= 0)) return Status::error("adaptive_threshold: must be >= 0");
    if (!(settings.polyline_tolerance_px > 0)) return Status::error("polyline_tolerance_px: must be > 0");
    if ((unsigned(settings.aovs) & ~unsigned(RenderAov::All)) != 0) return Status::error("aovs: unknown AOV bits");
    auto setup_r = make_setup(scene, cam, settings);
    if (!setup_r) return setup_r.status();
    const Setup& setup = setup_r.value();
    const int min_spp = std::min(settings.min_spp, settings.spp);

    const Roi disp = cam.display_window();
    rt::FlatLayout layout;
    if (flat) {
        std::vector<ChannelSpec> specs;
        layout = rt::FlatLayout::make(settings.aovs, specs);
        *flat = Image(specs, disp, disp);
        cam.to_metadata(flat->metadata);
        flat->metadata.set_string("gdof:renderCamera", setup.label);
    }
    std::vector<std::vector<rt::DeepSurface>> deep_pixels(deep ? disp.npixels() : 0);
    const bool want_id = has(settings.aovs, RenderAov::Id);
    // Unjittered pinhole: sample 0 is the central ray, its hit gives the id.
    const bool sample0_central = setup.mode == Mode::Pinhole && !(settings.pixel_jitter && settings.spp > 1);

    rt::LightSampler lights(scene);
    // A visible (non-black) environment is part of the picture: alpha 1.
    const bool env_opaque = scene.environment.x > 0 || scene.environment.y > 0 || scene.environment.z > 0;
    const int ts = settings.tile_size;
    const int ntx = (disp.width() + ts - 1) / ts, nty = (disp.height() + ts - 1) / ts;
    const long ntiles = long(ntx) * nty;
    std::atomic<std::uint64_t> a_primary{0}, a_segments{0}, a_shadow{0}, a_id{0};
    std::atomic<long> tiles_done{0};
    std::atomic<bool> failed{false};
    std::mutex error_mu;
    std::string error;
    const auto t0 = std::chrono::steady_clock::now();

    // A depth-only field (thin_lens, focal_planes, ...) has the same cone at
    // every pixel: sample the field once and only move the central ray per pixel.
    std::optional<PixelCone> shared_cone;
    if (setup.mode == Mode::Polyline && setup.ncam->depth_only()) {
        PixelCone c;
        Status st = setup.ncam->prepare(disp.x0 + 0.5, disp.y0 + 0.5, c);
        if (!st) return st.prefix("blur field");
        shared_cone = std::move(c);
    }

    auto body = [&](long tb, long te) {
        const ScopedFlushDenormals ftz;
        PixelCone cone = shared_cone ? *shared_cone : PixelCone{};
        PolylineRay poly;
        std::vector<rt::Sample> samples;
        for (long tile = tb; tile < te; ++tile) {
            if (exec.is_cancelled() || failed) return;
            TileCounters c;
            const int tx0 = disp.x0 + int(tile % ntx) * ts, ty0 = disp.y0 + int(tile / ntx) * ts;
            const int tx1 = std::min(tx0 + ts, disp.x1), ty1 = std::min(ty0 + ts, disp.y1);
            for (int y = ty0; y < ty1; ++y)
                for (int x = tx0; x < tx1; ++x) {
                    const double pcx = x + 0.5, pcy = y + 0.5;
                    const std::uint64_t seed = pixel_seed(x, y, settings.seed);
                    const std::uint64_t jitter_seed = rt::mix64(seed ^ 0x6a09e667f3bcc909ull);
                    const std::uint64_t pixel_key = rt::hash(std::uint64_t(std::uint32_t(x)), std::uint32_t(y));
                    if (setup.mode == Mode::Polyline && shared_cone) {
                        setup.ncam->retarget(cone, pcx, pcy);
                    } else if (setup.mode == Mode::Polyline) {
                        Status st = setup.ncam->prepare(pcx, pcy, cone);
                        if (!st) {  // the field cannot be sampled here: an error, never a silent pinhole
                            std::lock_guard<std::mutex> lock(error_mu);
                            if (!failed.exchange(true))
                                error = "blur field at pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                        "): " + st.message();
                            return;
                        }
                    }
                    LuminanceStats lum;
                    samples.clear();
                    for (int s = 0; s < settings.spp; ++s) {
                        if (s >= min_spp && lum.converged(settings.adaptive_threshold)) break;
                        Vec2 j{0, 0};
                        if (settings.pixel_jitter && settings.spp > 1) {
                            Vec2 u = unit_square_sample(jitter_seed, std::uint32_t(s));
                            j = {u.x - 0.5, u.y - 0.5};
                        }
                        const Vec2 ap = unit_square_sample(seed, std::uint32_t(s));
                        // Build the ray as a polyline: points, then far_direction.
                        if (setup.mode == Mode::Polyline && !cone.pinhole) {
                            setup.ncam->ray_from_unit(cone, ap, poly);
                            if (j.x != 0 || j.y != 0) {  // shift by the pixel offset, linear in depth
                                const Vec3 off = cam.right() * j.x + cam.up() * (-j.y);
                                const std::size_t n = poly.points.size();
                                const double dl = poly.depth[n - 1];
                                const double dpt = dot(poly.far_direction, cam.forward());
                                const Vec3 far_pt = poly.points[n - 1] + poly.far_direction * (1.0 / std::max(dpt, 1e-12)) +
                                                    off * setup.ncam->footprint(dl + 1.0);
                                for (std::size_t i = 0; i < n; ++i)
                                    poly.points[i] = poly.points[i] + off * setup.ncam->footprint(poly.depth[i]);
                                poly.far_direction = normalize(far_pt - poly.points[n - 1]);
                            }
                        } else {
                            CameraRay r = setup.mode == Mode::StraightThinLens
                                              ? thin_lens_ray(cam, pcx + j.x, pcy + j.y, setup.lens_radius,
                                                              setup.focus_depth, concentric_disc(ap))
                                              : cam.central_ray(pcx + j.x, pcy + j.y);
                            poly.points.assign(1, r.origin);
                            poly.far_direction = r.direction;
                        }
                        ++c.primary;
                        // Trace segment by segment, stopping at the first hit. Each
                        // segment reaches a little past its end vertex: a surface at an
                        // in-focus depth holds the vertex, and in float arithmetic
                        // neither segment would find it exactly at t = 1 / t = 0.
                        RayHit hit;
                        Vec3 o, d;
                        const std::size_t n = poly.points.size();
                        for (std::size_t i = 0; i < n && !hit.hit(); ++i) {
                            o = poly.points[i];
                            const bool last = i + 1 == n;
                            d = last ? poly.far_direction : poly.points[i + 1] - o;
                            ++c.segments;
                            hit = tracer.intersect(o, d, 0.0, last ? std::numeric_limits<double>::infinity() : 1.0 + 1e-4);
                        }
                        rt::Sample smp;
                        smp.radiance = scene.environment;
                        if (hit.hit()) {
                            rt::Rng rng(settings.seed, pixel_key, std::uint64_t(s));
                            const SurfaceHit sh = tracer.surface(hit, o, d);
                            smp.hit = true;
                            smp.radiance = lights.shade(tracer, sh, d, rng, settings.light_samples, c.shadow);
                            smp.albedo = scene.materials[sh.material].kd;
                            smp.p = sh.p;
                            smp.n = sh.n;
                            smp.z = cam.project(sh.p).depth;
                            smp.id = sh.object_id;
                        }
                        // The beauty is float: a sample beyond its range would write +inf.
                        const double peak = std::max({smp.radiance.x, smp.radiance.y, smp.radiance.z});
                        if (!(peak <= double(std::numeric_limits<float>::max()))) {
                            std::lock_guard<std::mutex> lock(error_mu);
                            if (!failed.exchange(true))
                                error = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + "): radiance " +
                                        std::to_string(peak) +
                                        " is beyond the float range of the beauty (a light's intensity or a "
                                        "material's emission is too large)";
                            return;
                        }
                        lum.add(rt::luminance(smp.radiance));
                        samples.push_back(smp);
                    }
                    // The id is the object on the pixel's central ray.
                    std::uint32_t id = 0;
                    if (want_id && flat && sample0_central) {
                        id = samples[0].hit ? samples[0].id : 0;
                    } else if (want_id && flat) {
                        const CameraRay cr = cam.central_ray(pcx, pcy);
                        ++c.id;
                        RayHit h = tracer.intersect(cr.origin, cr.direction, 0.0, std::numeric_limits<double>::infinity());
                        id = h.hit() ? scene.meshes[h.mesh].object_id[h.prim] : 0;
                    }
                    const std::size_t pix = std::size_t(y - disp.y0) * std::size_t(disp.width()) + std::size_t(x - disp.x0);
                    if (flat) rt::write_flat_pixel(*flat, layout, flat->offset(x, y), samples, id, env_opaque);
                    if (deep) rt::deep_pixel(samples, scene.environment, env_opaque, deep_pixels[pix]);
                }
            a_primary += c.primary, a_segments += c.segments, a_shadow += c.shadow, a_id += c.id;
            exec.report(double(++tiles_done) / double(ntiles));
        }
    };
    const bool done = parallel_for(exec, ntiles, body, 1);
    if (failed) return Status::error(error);
    if (!done) return Status::cancelled("render");
    if (stats) {
        stats->primary_rays = a_primary;
        stats->segments = a_segments;
        stats->shadow_rays = a_shadow;
        stats->id_rays = a_id;
        stats->sample_cap = std::uint64_t(disp.npixels()) * std::uint64_t(settings.spp);
        stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        stats->camera = setup.label;
    }
    if (deep) {
        auto made = rt::make_deep_image(disp, settings.aovs, deep_pixels);
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

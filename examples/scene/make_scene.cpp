// Generates gdof's bundled example: an analytic scene (checkered ground, an
// endless painted wall, spheres at several depths, thin poles close to the
// camera) ray-cast through a pinhole camera. Writes
//   - a flat multilayer EXR: R,G,B,A (half), Z (float), P.x/y/z (float),
//     N.x/y/z (half), id (uint), with worldToCamera/worldToNDC and lens
//     attributes, and
//   - optionally a deep EXR: per pixel one sample per object seen by the
//     pixel's subsamples (coverage as alpha), sorted front to back.
// Everything is computed from closed-form intersections, so the depth and
// position passes are exact ground truth for tests.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "gdof/camera.h"
#include "gdof/image_set.h"
#include "gdof/io/image_io.h"

namespace {

using gdof::Vec3;
constexpr double kInf = std::numeric_limits<double>::infinity();

struct Sphere {
    Vec3 c;
    double r;
    Vec3 albedo;
};
struct Pole {  // vertical cylinder from y=0 to y=h
    double x, z, r, h;
    Vec3 albedo;
};

struct Hit {
    double t = kInf;
    Vec3 p, n, albedo;
    unsigned id = 0;  // 0: nothing
};

struct Scene {
    std::vector<Sphere> spheres;
    std::vector<Pole> poles;
    double wall_z = 18.0;
    Vec3 light_dir = gdof::normalize(Vec3{-0.5, 1.0, -0.6});  // towards the light

    Hit intersect(const Vec3& o, const Vec3& d) const {
        Hit h;
        // Ground y = 0: checker of 0.5 units.
        if (d.y < 0) {
            double t = -o.y / d.y;
            if (t > 1e-6 && t < h.t) {
                Vec3 p = o + d * t;
                bool odd = (int(std::floor(p.x / 0.5)) + int(std::floor(p.z / 0.5))) & 1;
                h = {t, p, {0, 1, 0}, odd ? Vec3{0.75, 0.72, 0.65} : Vec3{0.18, 0.2, 0.24}, 1};
            }
        }
        // Wall z = wall_z facing the camera: concentric rings and stripes.
        if (d.z > 0) {
            double t = (wall_z - o.z) / d.z;
            if (t > 1e-6 && t < h.t) {
                Vec3 p = o + d * t;
                double ring = std::sin(std::hypot(p.x, p.y - 3.0) * 4.0);
                double stripe = std::sin(p.x * 9.0) * std::sin(p.y * 9.0);
                Vec3 a = ring > 0 ? Vec3{0.8, 0.45, 0.2} : Vec3{0.15, 0.35, 0.6};
                if (stripe > 0.6) a = {0.9, 0.9, 0.85};
                h = {t, p, {0, 0, -1}, a, 2};
            }
        }
        for (std::size_t i = 0; i < spheres.size(); ++i) {
            const Sphere& s = spheres[i];
            Vec3 oc = o - s.c;
            double b = gdof::dot(oc, d), c = gdof::dot(oc, oc) - s.r * s.r, disc = b * b - c;
            if (disc < 0) continue;
            double t = -b - std::sqrt(disc);
            if (t > 1e-6 && t < h.t) {
                Vec3 p = o + d * t;
                Vec3 n = (p - s.c) / s.r;
                // Latitude bands so defocus is visible on the spheres too.
                double band = std::sin(std::atan2(n.y, std::hypot(n.x, n.z)) * 10.0) > 0 ? 1.0 : 0.7;
                h = {t, p, n, s.albedo * band, unsigned(10 + i)};
            }
        }
        for (std::size_t i = 0; i < poles.size(); ++i) {
            const Pole& c = poles[i];
            double ox = o.x - c.x, oz = o.z - c.z;
            double a = d.x * d.x + d.z * d.z, b = ox * d.x + oz * d.z, cc = ox * ox + oz * oz - c.r * c.r;
            double disc = b * b - a * cc;
            if (a <= 0 || disc < 0) continue;
            double t = (-b - std::sqrt(disc)) / a;
            Vec3 p = o + d * t;
            if (t > 1e-6 && t < h.t && p.y >= 0 && p.y <= c.h)
                h = {t, p, gdof::normalize(Vec3{p.x - c.x, 0, p.z - c.z}), c.albedo, unsigned(30 + i)};
        }
        return h;
    }

    Vec3 shade(const Hit& h) const {
        double ndl = std::max(0.0, gdof::dot(h.n, light_dir));
        if (ndl > 0) {
            Hit s = intersect(h.p + h.n * 1e-4, light_dir);
            if (s.id != 0 && s.id != 2) ndl = 0;  // the wall does not shadow (it is behind)
        }
        double ambient = 0.25 + 0.1 * h.n.y;
        double light = 2.2 * ndl + ambient;
        return h.albedo * light;
    }
};

Scene make_scene() {
    Scene s;
    s.spheres = {{{-0.9, 0.45, 2.2}, 0.45, {0.8, 0.15, 0.1}},
                 {{0.7, 0.7, 4.5}, 0.7, {0.2, 0.7, 0.25}},
                 {{-1.8, 1.0, 8.0}, 1.0, {0.25, 0.3, 0.85}},
                 {{3.2, 1.6, 13.0}, 1.6, {0.85, 0.75, 0.2}}};
    s.poles = {{0.25, 1.2, 0.02, 3.0, {0.9, 0.9, 0.9}}, {-0.35, 1.6, 0.015, 3.0, {0.6, 0.6, 0.6}}};
    return s;
}

struct Options {
    int width = 640, height = 360, subsamples = 3;
    std::string flat_path, deep_path;
};

int usage() {
    std::fprintf(stderr,
                 "usage: gdof_example_scene [--size WxH] [--subsamples N] [-o flat.exr] [--deep deep.exr]\n"
                 "Writes gdof's generated example scene (RGBA, Z, P, N, id + camera attributes).\n");
    return 2;
}

}  // namespace

int main(int argc, char** argv) {
    Options opt;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        auto next = [&]() -> const char* { return i + 1 < argc ? argv[++i] : nullptr; };
        if (a == "--size") {
            const char* v = next();
            if (!v || std::sscanf(v, "%dx%d", &opt.width, &opt.height) != 2 || opt.width < 1 || opt.height < 1 ||
                opt.width > 16384 || opt.height > 16384) {
                std::fprintf(stderr, "gdof_example_scene: error: --size expects WxH (1..16384), got '%s'\n",
                             v ? v : "");
                return 2;
            }
        } else if (a == "--subsamples") {
            const char* v = next();
            opt.subsamples = v ? std::atoi(v) : 0;
            if (opt.subsamples < 1 || opt.subsamples > 16) {
                std::fprintf(stderr, "gdof_example_scene: error: --subsamples expects 1..16\n");
                return 2;
            }
        } else if (a == "-o") {
            const char* v = next();
            if (!v) return usage();
            opt.flat_path = v;
        } else if (a == "--deep") {
            const char* v = next();
            if (!v) return usage();
            opt.deep_path = v;
        } else {
            std::fprintf(stderr, "gdof_example_scene: error: unknown argument '%s'\n", a.c_str());
            return usage();
        }
    }
    if (opt.flat_path.empty() && opt.deep_path.empty()) return usage();

    gdof::CameraDesc desc;
    desc.position = {0.0, 1.1, -1.0};
    desc.look_at = {0.0, 0.9, 6.0};
    desc.focal_length_mm = 35.0;
    desc.sensor_width_mm = 36.0;
    desc.display_window = {0, 0, opt.width, opt.height};
    desc.f_number = 2.8;
    desc.focus_distance = 4.5;
    auto cam = gdof::Camera::create(desc);
    if (!cam) {
        std::fprintf(stderr, "gdof_example_scene: error: %s\n", cam.message().c_str());
        return 1;
    }
    const Scene scene = make_scene();
    const int W = opt.width, H = opt.height, S = opt.subsamples;
    const gdof::Roi win{0, 0, W, H};

    using gdof::PixelType;
    gdof::Image flat({{"R", PixelType::Half}, {"G", PixelType::Half}, {"B", PixelType::Half}, {"A", PixelType::Half},
                      {"Z", PixelType::Float}, {"P.x", PixelType::Float}, {"P.y", PixelType::Float},
                      {"P.z", PixelType::Float}, {"N.x", PixelType::Half}, {"N.y", PixelType::Half},
                      {"N.z", PixelType::Half}, {"id", PixelType::UInt}},
                     win);
    cam->to_metadata(flat.metadata);
    flat.metadata.set_string("Software", "gdof_example_scene");

    // Deep samples gathered per pixel: (id, summed colour, count, nearest depth).
    struct DeepSample {
        unsigned id;
        Vec3 rgb;
        int n;
        double z;
    };
    std::vector<std::vector<DeepSample>> deep(opt.deep_path.empty() ? 0 : std::size_t(W) * std::size_t(H));

    for (int y = 0; y < H; ++y) {
        for (int x = 0; x < W; ++x) {
            Vec3 sum{0, 0, 0};
            std::vector<DeepSample> samples;
            for (int sy = 0; sy < S; ++sy)
                for (int sx = 0; sx < S; ++sx) {
                    gdof::CameraRay ray = cam->central_ray(x + (sx + 0.5) / S, y + (sy + 0.5) / S);
                    Hit h = scene.intersect(ray.origin, ray.direction);
                    Vec3 c = scene.shade(h);
                    sum = sum + c;
                    if (!deep.empty()) {
                        double z = h.t * ray.depth_per_t;
                        auto it = std::find_if(samples.begin(), samples.end(),
                                               [&](const DeepSample& d) { return d.id == h.id; });
                        if (it == samples.end())
                            samples.push_back({h.id, c, 1, z});
                        else {
                            it->rgb = it->rgb + c;
                            it->n += 1;
                            it->z = std::min(it->z, z);
                        }
                    }
                }
            const std::size_t o = flat.offset(x, y);
            const double inv = 1.0 / (S * S);
            flat.plane(0)[o] = float(sum.x * inv);
            flat.plane(1)[o] = float(sum.y * inv);
            flat.plane(2)[o] = float(sum.z * inv);
            flat.plane(3)[o] = 1.0f;
            // Data passes come from the pixel centre, as renderers write them.
            gdof::CameraRay ray = cam->central_ray(x + 0.5, y + 0.5);
            Hit h = scene.intersect(ray.origin, ray.direction);
            flat.plane(4)[o] = float(h.t * ray.depth_per_t);
            flat.plane(5)[o] = float(h.p.x);
            flat.plane(6)[o] = float(h.p.y);
            flat.plane(7)[o] = float(h.p.z);
            flat.plane(8)[o] = float(h.n.x);
            flat.plane(9)[o] = float(h.n.y);
            flat.plane(10)[o] = float(h.n.z);
            flat.uplane(11)[o] = h.id;
            if (!deep.empty()) {
                std::sort(samples.begin(), samples.end(), [](const DeepSample& a, const DeepSample& b) {
                    return a.z < b.z;
                });
                deep[o] = std::move(samples);
            }
        }
    }

    if (!opt.flat_path.empty()) {
        gdof::ImageSet set;
        set.parts.emplace_back(std::move(flat));
        if (auto st = gdof::io::write_image(opt.flat_path, set); !st) {
            std::fprintf(stderr, "gdof_example_scene: error: %s\n", st.message().c_str());
            return 1;
        }
    }
    if (!opt.deep_path.empty()) {
        gdof::DeepImage d({{"R", PixelType::Half}, {"G", PixelType::Half}, {"B", PixelType::Half},
                           {"A", PixelType::Half}, {"Z", PixelType::Float}, {"id", PixelType::UInt}},
                          win, win);
        std::vector<std::uint32_t> counts(deep.size());
        for (std::size_t i = 0; i < deep.size(); ++i) counts[i] = std::uint32_t(deep[i].size());
        if (auto st = d.set_sample_counts(counts); !st) {
            std::fprintf(stderr, "gdof_example_scene: error: %s\n", st.message().c_str());
            return 1;
        }
        const double inv = 1.0 / (S * S);
        for (std::size_t i = 0; i < deep.size(); ++i) {
            std::size_t k = d.first_sample(i);
            for (const DeepSample& s : deep[i]) {
                // Premultiplied colour of the covered fraction; alpha = coverage.
                d.samples(0)[k] = float(s.rgb.x * inv);
                d.samples(1)[k] = float(s.rgb.y * inv);
                d.samples(2)[k] = float(s.rgb.z * inv);
                d.samples(3)[k] = float(s.n * inv);
                d.samples(4)[k] = float(s.z);
                d.usamples(5)[k] = s.id;
                ++k;
            }
        }
        cam->to_metadata(d.metadata);
        gdof::ImageSet set;
        set.parts.emplace_back(std::move(d));
        if (auto st = gdof::io::write_image(opt.deep_path, set); !st) {
            std::fprintf(stderr, "gdof_example_scene: error: %s\n", st.message().c_str());
            return 1;
        }
    }
    return 0;
}

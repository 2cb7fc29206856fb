// The method benchmark's cached inputs of one scene, for the benchmarks that
// run on them (bench_focus_pull, bench_pan): their command line (--out DIR
// --cache DIR) and the scene's camera, plate and deep render at 640x360.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "bench_cli.h"
#include "gdof/image_set.h"
#include "gdof/io/image_io.h"
#include "gdof/scene.h"

namespace gdof::bench {

// --out DIR --cache DIR (defaults bench_out, bench_cache).
struct OutAndCache {
    std::string out = "bench_out", cache = "bench_cache";
};
inline OutAndCache out_and_cache(int argc, char** argv) {
    OutAndCache o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--out") o.out = option_value(argc, argv, i);
        else if (a == "--cache") o.cache = option_value(argc, argv, i);
        else die("unknown argument '" + a + "' (--out DIR --cache DIR)");
    }
    std::filesystem::create_directories(o.out);
    return o;
}

// examples/render/NAME.json at width x height, and the method benchmark's
// plate (pinhole_q.exr: flat RGBA + Z) and deep render (deep_q.exr) of it
// from CACHE/NAME_WxH (dies, saying how to make them, when they are missing).
struct CachedScene {
    std::string path, dir;  // the scene file, the cache folder
    Scene scene;
    ImageSet plate, deep;
};
inline CachedScene cached_scene(const std::string& cache, const std::string& name, int width, int height) {
    namespace fs = std::filesystem;
    CachedScene c;
    c.path = GDOF_SOURCE_DIR "/examples/render/" + name + ".json";
    c.dir = cache + "/" + name + "_" + std::to_string(width) + "x" + std::to_string(height);
    for (const char* f : {"/pinhole_q.exr", "/deep_q.exr"})
        if (!fs::exists(c.dir + f))
            die(c.dir + f + " is missing: run the method benchmark first (tests/bench/run, or bench_methods --sizes " +
                std::to_string(width) + "x" + std::to_string(height) + " --scenes " + name + " --methods diffusion)");
    std::ifstream in(c.path);
    if (!in) die("cannot read " + c.path);
    nlohmann::json j = nlohmann::json::parse(in);
    j["camera"]["resolution"] = {width, height};
    c.scene = take(parse_scene(j.dump(), fs::path(c.path).parent_path().string()), c.path);
    c.plate.parts.emplace_back(take(io::read_flat(c.dir + "/pinhole_q.exr"), "plate"));
    c.deep = take(io::read_image(c.dir + "/deep_q.exr"), "deep render");
    return c;
}

}  // namespace gdof::bench

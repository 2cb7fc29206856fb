// The input files of the bad-input catalogue (bad_inputs.txt), made on
// demand by name into a row's folder: good files from the example scene and
// small hand-written ones, and damaged files derived from them (truncated,
// overwritten, NaN, a huge header, mismatched sizes). A name is made once per
// folder; a fixture may need others (make() recurses).
#pragma once

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <string>

#include "cli/cli_test_helpers.h"
#include "gdof/io/image_io.h"

namespace gdof::test {

class Fixtures {
public:
    explicit Fixtures(std::string dir) : dir_(std::move(dir)) {}
    const std::string& dir() const { return dir_; }

    // The path of fixture `name`, made if needed; "" (and a test failure) for an unknown name.
    std::string make(const std::string& name) {
        const std::string path = dir_ + "/" + name;
        if (fs::exists(path)) return path;
        const auto& makers = table();
        auto it = makers.find(name);
        if (it == makers.end()) {
            ADD_FAILURE() << "bad_inputs.txt names an unknown fixture {" << name << "}";
            return "";
        }
        it->second(*this, path);
        EXPECT_TRUE(fs::exists(path)) << "fixture " << name << " was not made";
        return path;
    }

private:
    using Maker = std::function<void(Fixtures&, const std::string& path)>;

    static std::string bytes_of(const std::string& path) { return read_text(path); }
    static void write_bytes(const std::string& path, const std::string& bytes) {
        std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
    }
    // The example scene (flat RGBA, Z, P, N, id with its camera) or its deep version.
    void example(const std::string& flat, const std::string& deep) {
        auto r = run_command(std::string("'") + GDOF_EXAMPLE_SCENE_PATH + "' --size 48x27 --subsamples 1 -o " +
                             quote(flat) + " --deep " + quote(deep));
        EXPECT_EQ(r.exit_code, 0) << r.output;
    }
    // The example scene with `edit(x, y, channel name, value)` applied to its float pixels.
    void edited(const std::string& path, const std::function<float(int, int, const std::string&, float)>& edit) {
        auto in = io::read_flat(make("scene.exr"));
        ASSERT_TRUE(in) << in.message();
        Image img = in.value();
        for (int c = 0; c < img.nchannels(); ++c) {
            if (img.channel(c).type == PixelType::UInt) continue;  // the id channel stays as it is
            for (int y = img.data_window().y0; y < img.data_window().y1; ++y)
                for (int x = img.data_window().x0; x < img.data_window().x1; ++x)
                    img.at(c, x, y) = edit(x, y, img.channel(c).name, img.at(c, x, y));
        }
        ASSERT_TRUE(io::write_flat(path, img));
    }
    // An RGBA + Z image of w x h without camera attributes.
    static void plain(const std::string& path, int w, int h, std::vector<std::string> channels = {"R", "G", "B", "A", "Z"}) {
        write_exr(path, w, h, channels, [](int x, int y, int c) { return c == 4 ? 2.0f + float(x) * 0.1f : 0.5f; });
    }
    static float sweep_texture(int x, int y, int c) { return 0.3f + 0.1f * float((x * 7 + y * 3 + c) % 5); }
    static void sweep_frames(const std::string& dir, int n) {
        fs::create_directories(dir);
        for (int k = 1; k <= n; ++k)
            write_exr(dir + "/f.000" + std::to_string(k) + ".exr", 24, 16, {"R", "G", "B"}, sweep_texture);
    }
    // Overwrites the four int32 of a box2i attribute (dataWindow/displayWindow) in an EXR header.
    static void patch_box(std::string& bytes, const std::string& attribute, int x0, int y0, int x1, int y1) {
        const std::string key = attribute + std::string(1, '\0') + "box2i" + std::string(1, '\0');
        const std::size_t at = bytes.find(key);
        ASSERT_NE(at, std::string::npos) << attribute;
        const int v[4] = {x0, y0, x1, y1};
        std::memcpy(&bytes[at + key.size() + 4], v, sizeof v);  // after the 4-byte attribute size
    }

    static const std::map<std::string, Maker>& table();
    std::string dir_;
};

inline const std::map<std::string, Fixtures::Maker>& Fixtures::table() {
    static const std::map<std::string, Maker> t = {
        // ---- good files
        {"scene.exr", [](Fixtures& f, const std::string& p) { f.example(p, f.dir() + "/deep.exr"); }},
        {"deep.exr", [](Fixtures& f, const std::string& p) { f.example(f.dir() + "/scene.exr", p); }},
        {"plain.exr", [](Fixtures&, const std::string& p) { plain(p, 16, 9); }},
        {"plain_20x10.exr", [](Fixtures&, const std::string& p) { plain(p, 20, 10); }},
        {"rgba_only.exr", [](Fixtures&, const std::string& p) { plain(p, 16, 9, {"R", "G", "B", "A"}); }},
        {"field.json", [](Fixtures&, const std::string& p) {
             write_text(p, R"({"blurfield": {"kind": "focal_planes", "depths": [3, 12], "max_blur": 4, "slope": 4}})");
         }},
        {"surfaces.json", [](Fixtures&, const std::string& p) {
             write_text(p, R"({"near": 1, "far": 3})");
         }},
        {"views", [](Fixtures&, const std::string& p) {
             fs::create_directories(p);
             for (int r = 0; r < 2; ++r)
                 for (int c = 0; c < 2; ++c)
                     plain(p + "/v_0" + std::to_string(r) + "_0" + std::to_string(c) + ".exr", 12, 8, {"R", "G", "B"});
         }},
        {"lf.json", [](Fixtures&, const std::string& p) { write_text(p, R"({"disparity_at_infinity": 0})"); }},
        {"lfstack.json", [](Fixtures&, const std::string& p) {
             write_text(p, R"({"disparities": [0], "apertures": [1]})");
         }},
        {"tri.obj", [](Fixtures&, const std::string& p) { write_text(p, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"); }},
        // ---- damaged images
        {"truncated_header.exr", [](Fixtures& f, const std::string& p) { write_bytes(p, bytes_of(f.make("scene.exr")).substr(0, 64)); }},
        {"truncated_half.exr", [](Fixtures& f, const std::string& p) {
             const std::string b = bytes_of(f.make("scene.exr"));
             write_bytes(p, b.substr(0, b.size() / 2));
         }},
        {"truncated_deep.exr", [](Fixtures& f, const std::string& p) {
             const std::string b = bytes_of(f.make("deep.exr"));
             write_bytes(p, b.substr(0, b.size() * 2 / 3));
         }},
        {"garbled_header.exr", [](Fixtures& f, const std::string& p) {
             std::string b = bytes_of(f.make("scene.exr"));
             for (std::size_t i = 12; i < 90 && i < b.size(); ++i) b[i] = char(0xA5);
             write_bytes(p, b);
         }},
        {"garbled_pixels.exr", [](Fixtures& f, const std::string& p) {
             std::string b = bytes_of(f.make("scene.exr"));
             for (std::size_t i = b.size() * 3 / 4; i < b.size(); ++i) b[i] = char(i * 131);
             write_bytes(p, b);
         }},
        {"text.exr", [](Fixtures&, const std::string& p) { write_text(p, "this is not an image\n"); }},
        {"zero_bytes.exr", [](Fixtures&, const std::string& p) { write_text(p, ""); }},
        {"huge_header.exr", [](Fixtures&, const std::string& p) {
             // A valid 4x3 file whose header then claims 1e6 x 1e6 pixels.
             const std::string small = p + ".small.exr";
             plain(small, 4, 3, {"R", "G", "B", "A"});
             std::string b = bytes_of(small);
             fs::remove(small);
             patch_box(b, "dataWindow", 0, 0, 999999, 999999);
             patch_box(b, "displayWindow", 0, 0, 999999, 999999);
             write_bytes(p, b);
         }},
        {"nan_depth.exr", [](Fixtures& f, const std::string& p) {
             f.edited(p, [](int x, int y, const std::string& c, float v) {
                 return (c == "Z" && x > 10 && x < 20 && y > 5 && y < 12) ? std::numeric_limits<float>::quiet_NaN() : v;
             });
         }},
        {"all_nan_depth.exr", [](Fixtures& f, const std::string& p) {
             f.edited(p, [](int, int, const std::string& c, float v) {
                 return c == "Z" || c.rfind("P.", 0) == 0 ? std::numeric_limits<float>::quiet_NaN() : v;
             });
         }},
        {"negative_depth.exr", [](Fixtures& f, const std::string& p) {
             f.edited(p, [](int, int, const std::string& c, float v) { return c == "Z" ? -v : v; });
         }},
        {"nan_colour.exr", [](Fixtures& f, const std::string& p) {
             f.edited(p, [](int x, int y, const std::string& c, float v) {
                 return (c == "R" && x == 20 && y == 10) ? std::numeric_limits<float>::quiet_NaN() : v;
             });
         }},
        {"inf_colour.exr", [](Fixtures& f, const std::string& p) {
             f.edited(p, [](int x, int y, const std::string& c, float v) {
                 return (c == "G" && x == 7 && y == 3) ? std::numeric_limits<float>::infinity() : v;
             });
         }},
        {"empty_window.exr", [](Fixtures&, const std::string& p) {
             Image img = Image::with_channels({"R", "G", "B", "A", "Z"}, Roi{0, 0, 0, 0});
             img.set_display_window(Roi{0, 0, 16, 9});
             ASSERT_TRUE(io::write_flat(p, img));
         }},
        {"depth_10x5.exr", [](Fixtures&, const std::string& p) { plain(p, 10, 5, {"Z"}); }},
        {"views_mixed", [](Fixtures&, const std::string& p) {
             fs::create_directories(p);
             for (int r = 0; r < 2; ++r)
                 for (int c = 0; c < 2; ++c)
                     plain(p + "/v_0" + std::to_string(r) + "_0" + std::to_string(c) + ".exr", r + c == 2 ? 10 : 12, 8,
                           {"R", "G", "B"});
         }},
        {"views_gap", [](Fixtures&, const std::string& p) {
             fs::create_directories(p);
             for (int r = 0; r < 2; ++r)
                 for (int c = 0; c < 2; ++c)
                     if (r + c != 1) plain(p + "/v_0" + std::to_string(r) + "_0" + std::to_string(c) + ".exr", 12, 8, {"R", "G", "B"});
         }},
        // ---- focus sweeps: folders of frames f.0001.exr ... (24x16, textured)
        {"sweep", [](Fixtures&, const std::string& p) { sweep_frames(p, 3); }},
        {"sweep_one", [](Fixtures&, const std::string& p) { sweep_frames(p, 1); }},
        {"sweep_flat", [](Fixtures&, const std::string& p) {
             fs::create_directories(p);
             for (int k = 1; k <= 3; ++k) plain(p + "/f.000" + std::to_string(k) + ".exr", 24, 16, {"R", "G", "B"});
         }},
        {"sweep_mixed", [](Fixtures&, const std::string& p) {
             sweep_frames(p, 3);
             plain(p + "/f.0002.exr", 20, 16, {"R", "G", "B"});
         }},
        {"sweep_nan", [](Fixtures&, const std::string& p) {
             sweep_frames(p, 3);
             write_exr(p + "/f.0002.exr", 24, 16, {"R", "G", "B"}, [](int x, int y, int c) {
                 return x == 5 && y == 3 && c == 1 ? std::numeric_limits<float>::quiet_NaN() : sweep_texture(x, y, c);
             });
         }},
        {"sweep_unordered", [](Fixtures&, const std::string& p) {
             sweep_frames(p, 3);
             write_text(p + "/manifest.json", R"({"gdof_stack": 1, "focal_length_mm": 50, "sensor_width_mm": 36, "width": 24, "height": 16, "references": [
                 {"file": "f.0001.exr", "focus_distance": 1, "f_number": 2},
                 {"file": "f.0002.exr", "focus_distance": 3, "f_number": 2},
                 {"file": "f.0003.exr", "focus_distance": 2, "f_number": 2}]})");
         }},
        // ---- damaged text
        {"truncated.json", [](Fixtures&, const std::string& p) { write_text(p, R"({"blurfield": {"kind": "focal_planes", )"); }},
        {"empty.json", [](Fixtures&, const std::string& p) { write_text(p, ""); }},
        {"array.json", [](Fixtures&, const std::string& p) { write_text(p, "[1, 2, 3]"); }},
        {"binary.json", [](Fixtures&, const std::string& p) { write_text(p, std::string("\x89PNG\r\n\x1a\n\0\0", 10)); }},
        {"unknown_key.json", [](Fixtures&, const std::string& p) {
             write_text(p, R"({"blurfield": {"kind": "focal_planes", "depths": [3], "max_blurr": 4}})");
         }},
        {"unknown_kind.json", [](Fixtures&, const std::string& p) { write_text(p, R"({"blurfield": {"kind": "tilt_shift"}})"); }},
        {"nan_field.json", [](Fixtures&, const std::string& p) {
             write_text(p, R"({"blurfield": {"kind": "focal_planes", "depths": [NaN], "max_blur": 4}})");
         }},
        {"radius_1e9.json", [](Fixtures&, const std::string& p) {
             write_text(p, R"({"blurfield": {"kind": "focal_planes", "depths": [3], "max_blur": 1e9, "slope": 1e9}})");
         }},
        {"negative_blur.json", [](Fixtures&, const std::string& p) {
             write_text(p, R"({"blurfield": {"kind": "focal_planes", "depths": [3], "max_blur": -2}})");
         }},
        {"psf_unknown_key.json", [](Fixtures&, const std::string& p) {
             write_text(p, R"({"psf_field": {"kind": "sum", "children": [{"kind": "defocus"}, {"kind": "swirl", "strenght": 2}]}})");
         }},
        {"psf_missing_map.json", [](Fixtures&, const std::string& p) {
             write_text(p, R"({"psf_field": {"kind": "blend", "weight": {"kind": "image_map", "image": "no_such_weight.exr", "scale": 1},
                                              "children": [{"kind": "defocus"}, {"kind": "swirl"}]}})");
         }},
        {"missing_mask.json", [](Fixtures&, const std::string& p) {
             write_text(p, R"({"blurfield": {"kind": "image_map", "image": "no_such_mask.exr", "scale": 3}})");
         }},
        {"surfaces_bad.json", [](Fixtures&, const std::string& p) {
             write_text(p, R"({"near": {"grid": [[1, 2], [1]]}, "far": 3})");
         }},
        {"scene_syntax.json", [](Fixtures&, const std::string& p) { write_text(p, "{\"camera\": {\n  \"position\": [0, 0, 0],,\n}}"); }},
        {"scene_missing_mesh.json", [](Fixtures&, const std::string& p) {
             write_text(p, R"({"camera": {"position": [0, 0, -3], "look_at": [0, 0, 0], "focal_length_mm": 50},
                               "meshes": [{"file": "no_such_mesh.obj"}]})");
         }},
        {"scene_nan_obj.json", [](Fixtures& f, const std::string& p) {
             f.make("nan.obj");
             write_text(p, R"({"camera": {"position": [0, 0, -3], "look_at": [0, 0, 0], "focal_length_mm": 50},
                               "meshes": [{"file": "nan.obj"}]})");
         }},
        {"scene_bad_index.json", [](Fixtures& f, const std::string& p) {
             f.make("bad_index.obj");
             write_text(p, R"({"camera": {"position": [0, 0, -3], "look_at": [0, 0, 0], "focal_length_mm": 50},
                               "meshes": [{"file": "bad_index.obj"}]})");
         }},
        {"scene_camera_inside_out.json", [](Fixtures& f, const std::string& p) {
             f.make("tri.obj");
             write_text(p, R"({"camera": {"position": [0, 0, -3], "look_at": [0, 0, -3], "focal_length_mm": 50},
                               "meshes": [{"file": "tri.obj"}]})");
         }},
        {"nan.obj", [](Fixtures&, const std::string& p) { write_text(p, "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"); }},
        {"bad_index.obj", [](Fixtures&, const std::string& p) { write_text(p, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n"); }},
        {"manifest_missing_file.json", [](Fixtures&, const std::string& p) {
             write_text(p, R"({"width": 16, "height": 9, "references": [{"file": "gone.exr", "focus_distance": 2, "f_number": 2.8, "near": 1, "far": 2},
                                {"file": "gone2.exr", "focus_distance": 3, "f_number": 2.8, "near": 2, "far": 4}]})");
         }},
        {"manifest_empty.json", [](Fixtures&, const std::string& p) { write_text(p, R"({"references": []})"); }},
        {"manifest_sizes.json", [](Fixtures& f, const std::string& p) {
             f.make("plain.exr");
             f.make("plain_20x10.exr");
             write_text(p, R"({"references": [{"file": "plain.exr", "focus_distance": 2, "f_number": 2.8, "near": 1, "far": 2},
                                {"file": "plain_20x10.exr", "focus_distance": 3, "f_number": 2.8, "near": 2, "far": 4}]})");
         }},
        {"manifest_f0.json", [](Fixtures& f, const std::string& p) {
             f.make("plain.exr");
             write_text(p, R"({"width": 16, "height": 9, "coc_px": 1, "sensor_width_mm": 36,
                               "references": [{"file": "plain.exr", "focus_distance": 2, "f_number": 0, "focal_length_mm": 50}]})");
         }},
        {"manifest_lens_table.json", [](Fixtures& f, const std::string& p) {
             f.make("lens.csv");
             write_text(p, R"({"pattern": "plain.####.exr", "table": "lens.csv"})");
         }},
        {"lens.csv", [](Fixtures&, const std::string& p) { write_text(p, "frame,focus_distance,f_number\n1,2,2.8\n2,\"4,2.8\n"); }},
        {"lens_pull.csv", [](Fixtures&, const std::string& p) { write_text(p, "frame,focus_distance\n1,2\n9,4\n"); }},
        {"lf_bad.json", [](Fixtures&, const std::string& p) { write_text(p, R"({"disparity_at_infinity": "far"})"); }},
        {"lfstack_empty.json", [](Fixtures&, const std::string& p) { write_text(p, R"({"disparities": [], "apertures": [1]})"); }},
    };
    return t;
}

}  // namespace gdof::test

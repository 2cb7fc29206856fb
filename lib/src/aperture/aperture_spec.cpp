// The aperture's values: their checks and the CLI form
// ("polygon:6:15,roundness=0.2") both ways.
#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "common/format_number.h"
#include "gdof/aperture.h"

namespace gdof {

namespace {

std::string num(double v) { return format_number(v, 6); }

// Whole string as a finite number, else nullopt.
bool to_number(const std::string& s, double& out) {
    if (s.empty()) return false;
    char* end = nullptr;
    out = std::strtod(s.c_str(), &end);
    return end == s.c_str() + s.size() && std::isfinite(out);
}

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> out;
    std::size_t start = 0;
    for (;;) {
        const std::size_t k = s.find(sep, start);
        out.push_back(s.substr(start, k == std::string::npos ? std::string::npos : k - start));
        if (k == std::string::npos) return out;
        start = k + 1;
    }
}

}  // namespace

const char* to_string(Aperture::Kind kind) {
    switch (kind) {
        case Aperture::Kind::Disc: return "disc";
        case Aperture::Kind::Polygon: return "polygon";
        case Aperture::Kind::Image: return "image";
    }
    return "?";
}

Status validate(const Aperture& a) {
    const std::string p = "aperture: ";
    if (a.kind == Aperture::Kind::Polygon && (a.blades < 3 || a.blades > 64))
        return Status::error(p + "blades must be 3 to 64, got " + std::to_string(a.blades), StatusCode::InvalidArgument, "blades");
    if (!std::isfinite(a.rotation_deg)) return Status::error(p + "rotation must be finite, got " + num(a.rotation_deg), StatusCode::InvalidArgument, "rotation");
    if (!(a.roundness >= 0.0 && a.roundness <= 1.0))
        return Status::error(p + "roundness must be in [0, 1], got " + num(a.roundness), StatusCode::InvalidArgument, "roundness");
    if (!(a.squeeze >= 0.1 && a.squeeze <= 10.0))
        return Status::error(p + "squeeze must be in [0.1, 10], got " + num(a.squeeze), StatusCode::InvalidArgument, "squeeze");
    if (!(a.cats_eye >= 0.0 && a.cats_eye <= 1.0))
        return Status::error(p + "cats_eye must be in [0, 1], got " + num(a.cats_eye), StatusCode::InvalidArgument, "cats_eye");
    if (a.kind != Aperture::Kind::Image) return Status::ok();
    const std::string what = a.image_path.empty() ? std::string("the image kernel") : "image kernel '" + a.image_path + "'";
    const Roi dw = a.image.data_window();
    if (dw.empty() || a.image.nchannels() == 0) return Status::error(p + what + " is empty", StatusCode::InvalidArgument, "image");
    const int nc = a.image.nchannels() >= 3 ? 3 : 1;
    double total = 0.0;
    for (int c = 0; c < nc; ++c)
        for (int y = dw.y0; y < dw.y1; ++y)
            for (int x = dw.x0; x < dw.x1; ++x) {
                const double v = a.image.sample(c, x, y);
                if (!std::isfinite(v) || v < 0.0)
                    return Status::error(p + what + ": channel '" + a.image.channel(c).name + "' is " + num(v) +
                                             " at pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                             "); a kernel must be finite and >= 0",
                                         StatusCode::InvalidArgument, "image");
                total += v;
            }
    if (!(total > 0.0)) return Status::error(p + what + " is all zero", StatusCode::InvalidArgument, "image");
    if (nc == 3)
        for (int c = 0; c < 3; ++c) {
            double t = 0.0;
            for (int y = dw.y0; y < dw.y1; ++y)
                for (int x = dw.x0; x < dw.x1; ++x) t += a.image.sample(c, x, y);
            if (!(t > 0.0))
                return Status::error(p + what + ": channel '" + a.image.channel(c).name +
                                         "' is all zero (each colour channel spreads by its own kernel)",
                                     StatusCode::InvalidArgument, "image");
        }
    return Status::ok();
}

Result<Aperture> parse_aperture(const std::string& spec) {
    const std::string p = "aperture '" + spec + "': ";
    Aperture a;
    // "image:FILE,key=v": the file name may hold ':' but not ','.
    const std::vector<std::string> items = split(spec, ',');
    const std::string& shape = items[0];
    if (shape == "disc") {
        a.kind = Aperture::Kind::Disc;
    } else if (shape.rfind("polygon", 0) == 0) {
        a.kind = Aperture::Kind::Polygon;
        const std::vector<std::string> f = split(shape, ':');
        if (f[0] != "polygon" || f.size() < 2 || f.size() > 3)
            return Status::error(p + "expected polygon:BLADES[:ROTATION_DEG]", StatusCode::InvalidArgument);
        double b = 0.0;
        if (!to_number(f[1], b) || b != std::floor(b))
            return Status::error(p + "blades '" + f[1] + "' is not a whole number", StatusCode::InvalidArgument, "blades");
        a.blades = int(std::clamp(b, -1.0, 1000.0));
        if (f.size() == 3 && !to_number(f[2], a.rotation_deg))
            return Status::error(p + "rotation '" + f[2] + "' is not a number", StatusCode::InvalidArgument, "rotation");
    } else if (shape.rfind("image:", 0) == 0) {
        a.kind = Aperture::Kind::Image;
        a.image_path = shape.substr(6);
        if (a.image_path.empty()) return Status::error(p + "expected image:FILE", StatusCode::InvalidArgument, "image");
    } else {
        return Status::error(p + "unknown shape '" + shape + "' (expected disc, polygon:BLADES[:ROTATION_DEG] or image:FILE)", StatusCode::InvalidArgument);
    }
    for (std::size_t i = 1; i < items.size(); ++i) {
        const std::size_t eq = items[i].find('=');
        const std::string key = items[i].substr(0, eq);
        const std::string val = eq == std::string::npos ? std::string() : items[i].substr(eq + 1);
        double v = 0.0;
        if (eq == std::string::npos || !to_number(val, v))
            return Status::error(p + "expected key=number, got '" + items[i] + "'", StatusCode::InvalidArgument, key);
        if (key == "roundness") a.roundness = v;
        else if (key == "squeeze") a.squeeze = v;
        else if (key == "cats_eye") a.cats_eye = v;
        else if (key == "rotation") a.rotation_deg = v;
        else return Status::error(p + "unknown key '" + key + "' (expected roundness, squeeze, cats_eye or rotation)", StatusCode::InvalidArgument, key);
    }
    if (Status st = validate(a); !st && a.kind != Aperture::Kind::Image) return st;
    return a;
}

std::string format_aperture(const Aperture& a) {
    std::string s;
    switch (a.kind) {
        case Aperture::Kind::Disc: s = "disc"; break;
        case Aperture::Kind::Polygon:
            s = "polygon:" + std::to_string(a.blades) + (a.rotation_deg != 0.0 ? ":" + num(a.rotation_deg) : "");
            break;
        case Aperture::Kind::Image:
            s = "image:" + a.image_path + (a.rotation_deg != 0.0 ? ",rotation=" + num(a.rotation_deg) : "");
            break;
    }
    if (a.roundness != 0.0) s += ",roundness=" + num(a.roundness);
    if (a.squeeze != 1.0) s += ",squeeze=" + num(a.squeeze);
    if (a.cats_eye != 0.0) s += ",cats_eye=" + num(a.cats_eye);
    return s;
}

}  // namespace gdof

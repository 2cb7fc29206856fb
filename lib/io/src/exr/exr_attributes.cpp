// OpenEXR header attributes <-> gdof::Metadata. See exr_attributes.h for the
// type table.
#include "exr/exr_attributes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string_view>

#include <OpenEXR/ImfBoxAttribute.h>
#include <OpenEXR/ImfChromaticitiesAttribute.h>
#include <OpenEXR/ImfDeepImageStateAttribute.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfEnvmapAttribute.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfFloatVectorAttribute.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfKeyCodeAttribute.h>
#include <OpenEXR/ImfLineOrderAttribute.h>
#include <OpenEXR/ImfMatrixAttribute.h>
#include <OpenEXR/ImfOpaqueAttribute.h>
#include <OpenEXR/ImfRationalAttribute.h>
#include <OpenEXR/ImfStdIO.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfStringVectorAttribute.h>
#include <OpenEXR/ImfTimeCodeAttribute.h>
#include <OpenEXR/ImfVecAttribute.h>
#include <OpenEXR/ImfVersion.h>

namespace gdof::io::detail {

namespace {

constexpr std::array<std::string_view, 11> kStructural = {
    "channels", "dataWindow", "displayWindow", "compression", "tiles",     "name",
    "view",     "type",       "version",       "chunkCount",  "gdof:emptyDataWindow"};

template <class M>
std::vector<double> matrix_numbers(const M& m, int n) {
    std::vector<double> v;
    v.reserve(std::size_t(n * n));
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c) v.push_back(double(m[r][c]));
    return v;
}

template <class M>
M numbers_matrix(const std::vector<double>& v, int n) {
    M m;
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c) m[r][c] = static_cast<std::remove_reference_t<decltype(m[0][0])>>(v[std::size_t(r * n + c)]);
    return m;
}

bool starts_with(std::string_view s, std::string_view p) { return s.substr(0, p.size()) == p; }

// Parses "base[N]" into base and N (N = 1 without brackets, -1 on a bad count).
void split_array_type(const std::string& type, std::string& base, long& count) {
    auto lb = type.find('[');
    if (lb == std::string::npos || type.back() != ']') {
        base = type;
        count = 1;
        return;
    }
    base = type.substr(0, lb);
    try {
        count = std::stol(type.substr(lb + 1, type.size() - lb - 2));
    } catch (...) {
        count = -1;
    }
}

int to_int(double v) {
    if (!(v >= double(std::numeric_limits<int>::min()) && v <= double(std::numeric_limits<int>::max()))) return 0;
    return int(std::llround(v));
}
unsigned to_uint(double v) {
    if (!(v >= 0 && v <= double(std::numeric_limits<unsigned>::max()))) return 0;
    return unsigned(std::llround(v));
}

}  // namespace

bool is_structural_exr_attribute(const std::string& name) {
    return std::find(kStructural.begin(), kStructural.end(), name) != kStructural.end();
}

static Attribute from_exr_attribute(const std::string& name, const Imf::Attribute& a) {
    using namespace Imf;
    Attribute out;
    out.name = name;
    const std::string t = a.typeName();
    auto set = [&](std::string type, std::vector<double> nums) {
        out.type = std::move(type);
        out.numbers = std::move(nums);
    };
    if (t == "int") set("int", {double(static_cast<const IntAttribute&>(a).value())});
    else if (t == "float") set("float", {double(static_cast<const FloatAttribute&>(a).value())});
    else if (t == "double") set("double", {static_cast<const DoubleAttribute&>(a).value()});
    else if (t == "string") {
        out.type = "string";
        out.text = static_cast<const StringAttribute&>(a).value();
    } else if (t == "stringvector") {
        const auto& v = static_cast<const StringVectorAttribute&>(a).value();
        out.type = "string[" + std::to_string(v.size()) + "]";
        for (std::size_t i = 0; i < v.size(); ++i) {
            if (i) out.text.push_back('\0');
            out.text += v[i];
        }
    } else if (t == "floatvector") {
        const auto& v = static_cast<const FloatVectorAttribute&>(a).value();
        set("float[" + std::to_string(v.size()) + "]", std::vector<double>(v.begin(), v.end()));
    } else if (t == "v2i") {
        auto v = static_cast<const V2iAttribute&>(a).value();
        set("vector2i", {double(v.x), double(v.y)});
    } else if (t == "v2f") {
        auto v = static_cast<const V2fAttribute&>(a).value();
        set("vector2", {double(v.x), double(v.y)});
    } else if (t == "v2d") {
        auto v = static_cast<const V2dAttribute&>(a).value();
        set("vector2d", {v.x, v.y});
    } else if (t == "v3i") {
        auto v = static_cast<const V3iAttribute&>(a).value();
        set("vector3i", {double(v.x), double(v.y), double(v.z)});
    } else if (t == "v3f") {
        auto v = static_cast<const V3fAttribute&>(a).value();
        set("vector", {double(v.x), double(v.y), double(v.z)});
    } else if (t == "v3d") {
        auto v = static_cast<const V3dAttribute&>(a).value();
        set("vector3d", {v.x, v.y, v.z});
    } else if (t == "m33f") set("matrix33", matrix_numbers(static_cast<const M33fAttribute&>(a).value(), 3));
    else if (t == "m33d") set("matrix33d", matrix_numbers(static_cast<const M33dAttribute&>(a).value(), 3));
    else if (t == "m44f") set("matrix", matrix_numbers(static_cast<const M44fAttribute&>(a).value(), 4));
    else if (t == "m44d") set("matrixd", matrix_numbers(static_cast<const M44dAttribute&>(a).value(), 4));
    else if (t == "box2i") {
        auto b = static_cast<const Box2iAttribute&>(a).value();
        set("box2i", {double(b.min.x), double(b.min.y), double(b.max.x), double(b.max.y)});
    } else if (t == "box2f") {
        auto b = static_cast<const Box2fAttribute&>(a).value();
        set("box2", {double(b.min.x), double(b.min.y), double(b.max.x), double(b.max.y)});
    } else if (t == "rational") {
        auto r = static_cast<const RationalAttribute&>(a).value();
        set("rational", {double(r.n), double(r.d)});
    } else if (t == "timecode") {
        auto tc = static_cast<const TimeCodeAttribute&>(a).value();
        set("timecode", {double(tc.timeAndFlags()), double(tc.userData())});
    } else if (t == "keycode") {
        auto k = static_cast<const KeyCodeAttribute&>(a).value();
        set("keycode", {double(k.filmMfcCode()), double(k.filmType()), double(k.prefix()), double(k.count()),
                        double(k.perfOffset()), double(k.perfsPerFrame()), double(k.perfsPerCount())});
    } else if (t == "chromaticities") {
        auto c = static_cast<const ChromaticitiesAttribute&>(a).value();
        set("float[8]", {c.red.x, c.red.y, c.green.x, c.green.y, c.blue.x, c.blue.y, c.white.x, c.white.y});
    } else if (t == "envmap") {
        set("int", {double(static_cast<const EnvmapAttribute&>(a).value())});
        out.text = "exr:envmap";
    } else if (t == "deepImageState") {
        set("int", {double(static_cast<const DeepImageStateAttribute&>(a).value())});
        out.text = "exr:deepImageState";
    } else if (t == "lineOrder") {
        set("int", {double(static_cast<const LineOrderAttribute&>(a).value())});
        out.text = "exr:lineOrder";
    } else {
        // Anything else keeps its raw bytes and EXR type name.
        StdOSStream os;
        a.writeValueTo(os, EXR_VERSION);
        const std::string bytes = os.str();
        out.type = "uint8[" + std::to_string(bytes.size()) + "]";
        out.text = "exr:" + t;
        out.numbers.reserve(bytes.size());
        for (unsigned char ch : bytes) out.numbers.push_back(double(ch));
    }
    return out;
}

void exr_header_to_metadata(const Imf::Header& header, Metadata& md) {
    for (auto it = header.begin(); it != header.end(); ++it) {
        std::string name = it.name();
        if (is_structural_exr_attribute(name)) continue;
        md.set(from_exr_attribute(name, it.attribute()));
    }
}

std::unique_ptr<Imf::Attribute> to_exr_attribute(const Attribute& a) {
    using namespace Imf;
    const auto& v = a.numbers;
    const std::size_t n = v.size();
    std::string base;
    long count = 1;
    split_array_type(a.type, base, count);

    // Opaque: raw bytes with their EXR type name.
    if (starts_with(a.text, "exr:") && base == "uint8") {
        auto attr = std::make_unique<OpaqueAttribute>(a.text.substr(4).c_str());
        std::string bytes;
        bytes.reserve(n);
        for (double d : v) bytes.push_back(char(static_cast<unsigned char>(to_uint(d))));
        StdISStream is;
        is.str(bytes);
        attr->readValueFrom(is, int(bytes.size()), EXR_VERSION);
        return attr;
    }
    if (base == "string") {
        if (count == 1 && a.type == "string") return std::make_unique<StringAttribute>(a.text);
        StringVector sv;
        if (count > 0) {
            std::size_t start = 0;
            while (true) {
                std::size_t z = a.text.find('\0', start);
                sv.push_back(a.text.substr(start, z == std::string::npos ? std::string::npos : z - start));
                if (z == std::string::npos) break;
                start = z + 1;
            }
        }
        return std::make_unique<StringVectorAttribute>(sv);
    }
    auto f = [&](std::size_t i) { return float(v[i]); };
    if (a.type == "int" || a.type == "uint" || a.type == "int64" || a.type == "uint64" || a.type == "int16" ||
        a.type == "uint16" || a.type == "uint8" || a.type == "int8") {
        if (n != 1) return nullptr;
        int i = to_int(v[0]);
        const std::string exr_type = starts_with(a.text, "exr:") ? a.text.substr(4) : std::string();
        if (exr_type == "envmap") return std::make_unique<EnvmapAttribute>(Envmap(i));
        if (exr_type == "deepImageState") return std::make_unique<DeepImageStateAttribute>(DeepImageState(i));
        if (exr_type == "lineOrder") return std::make_unique<LineOrderAttribute>(LineOrder(i));
        if (a.name == "envmap") return std::make_unique<EnvmapAttribute>(Envmap(i));
        if (a.name == "deepImageState") return std::make_unique<DeepImageStateAttribute>(DeepImageState(i));
        if (a.name == "lineOrder") return std::make_unique<LineOrderAttribute>(LineOrder(i));
        return std::make_unique<IntAttribute>(i);
    }
    if (a.type == "float" || a.type == "half") return n == 1 ? std::make_unique<FloatAttribute>(f(0)) : nullptr;
    if (a.type == "double") return n == 1 ? std::make_unique<DoubleAttribute>(v[0]) : nullptr;
    if (a.type == "vector2i" && n == 2) return std::make_unique<V2iAttribute>(Imath::V2i(to_int(v[0]), to_int(v[1])));
    if ((a.type == "vector2" || a.type == "float2") && n == 2) return std::make_unique<V2fAttribute>(Imath::V2f(f(0), f(1)));
    if (a.type == "vector2d" && n == 2) return std::make_unique<V2dAttribute>(Imath::V2d(v[0], v[1]));
    if (a.type == "vector3i" && n == 3)
        return std::make_unique<V3iAttribute>(Imath::V3i(to_int(v[0]), to_int(v[1]), to_int(v[2])));
    if ((a.type == "vector" || a.type == "point" || a.type == "normal" || a.type == "color" || a.type == "float3") &&
        n == 3)
        return std::make_unique<V3fAttribute>(Imath::V3f(f(0), f(1), f(2)));
    if (a.type == "vector3d" && n == 3) return std::make_unique<V3dAttribute>(Imath::V3d(v[0], v[1], v[2]));
    if (a.type == "matrix33" && n == 9) return std::make_unique<M33fAttribute>(numbers_matrix<Imath::M33f>(v, 3));
    if (a.type == "matrix33d" && n == 9) return std::make_unique<M33dAttribute>(numbers_matrix<Imath::M33d>(v, 3));
    if (a.type == "matrix" && n == 16) return std::make_unique<M44fAttribute>(numbers_matrix<Imath::M44f>(v, 4));
    if (a.type == "matrixd" && n == 16) return std::make_unique<M44dAttribute>(numbers_matrix<Imath::M44d>(v, 4));
    if (a.type == "box2i" && n == 4)
        return std::make_unique<Box2iAttribute>(
            Imath::Box2i(Imath::V2i(to_int(v[0]), to_int(v[1])), Imath::V2i(to_int(v[2]), to_int(v[3]))));
    if (a.type == "box2" && n == 4)
        return std::make_unique<Box2fAttribute>(Imath::Box2f(Imath::V2f(f(0), f(1)), Imath::V2f(f(2), f(3))));
    if (a.type == "rational" && n == 2) return std::make_unique<RationalAttribute>(Rational(to_int(v[0]), to_uint(v[1])));
    if (a.type == "timecode" && n == 2)
        return std::make_unique<TimeCodeAttribute>(TimeCode(to_uint(v[0]), to_uint(v[1])));
    if (a.type == "keycode" && n == 7)
        return std::make_unique<KeyCodeAttribute>(KeyCode(to_int(v[0]), to_int(v[1]), to_int(v[2]), to_int(v[3]),
                                                          to_int(v[4]), to_int(v[5]), to_int(v[6])));
    if (base == "float" && count >= 0 && std::size_t(count) == n) {
        if (a.name == "chromaticities" && n == 8)
            return std::make_unique<ChromaticitiesAttribute>(Chromaticities(
                Imath::V2f(f(0), f(1)), Imath::V2f(f(2), f(3)), Imath::V2f(f(4), f(5)), Imath::V2f(f(6), f(7))));
        FloatVector fv(n);
        for (std::size_t i = 0; i < n; ++i) fv[i] = f(i);
        return std::make_unique<FloatVectorAttribute>(fv);
    }
    if ((base == "int" || base == "double") && count >= 0 && std::size_t(count) == n) {
        if (base == "int" && n == 2) return std::make_unique<V2iAttribute>(Imath::V2i(to_int(v[0]), to_int(v[1])));
        if (base == "int" && n == 3)
            return std::make_unique<V3iAttribute>(Imath::V3i(to_int(v[0]), to_int(v[1]), to_int(v[2])));
        if (base == "double" && n == 2) return std::make_unique<V2dAttribute>(Imath::V2d(v[0], v[1]));
        if (base == "double" && n == 3) return std::make_unique<V3dAttribute>(Imath::V3d(v[0], v[1], v[2]));
        if (base == "double" && n == 16) return std::make_unique<M44dAttribute>(numbers_matrix<Imath::M44d>(v, 4));
        FloatVector fv(n);
        for (std::size_t i = 0; i < n; ++i) fv[i] = f(i);
        return std::make_unique<FloatVectorAttribute>(fv);
    }
    return nullptr;
}

static bool foreign_attribute(const std::string& name) {
    // OIIO bookkeeping and other formats' private attributes have no place in an EXR header.
    static constexpr std::array<std::string_view, 12> prefixes = {
        "oiio:", "openexr:", "png:", "jpeg:", "tiff:", "bmp:", "targa:", "gif:", "dpx:", "heif:", "webp:", "psd:"};
    for (auto p : prefixes)
        if (starts_with(name, p)) return true;
    return false;
}

void metadata_to_exr_header(const Metadata& md, Imf::Header& header) {
    for (const auto& a : md.attributes()) {
        if (a.name.empty() || is_structural_exr_attribute(a.name) || foreign_attribute(a.name)) continue;
        std::unique_ptr<Imf::Attribute> attr;
        try {
            attr = to_exr_attribute(a);
        } catch (const std::exception&) {
            attr.reset();  // e.g. a keycode out of range: not representable
        }
        if (!attr) continue;
        // A required attribute (pixelAspectRatio ...) of another type would make
        // insert() throw; such an attribute is dropped rather than failing the write.
        try {
            header.insert(a.name, *attr);
        } catch (const std::exception&) {
        }
    }
}

}  // namespace gdof::io::detail

// Images as Python objects: gdof.Roi, gdof.Metadata, gdof.Image,
// gdof.DeepImage and gdof.ImageSet. Pixels are numpy views of the library's
// own planes (no copy): an Image's float channels are (C, H, W) float32, a
// deep channel's samples one float32 (or uint32) array in sample order.
// What would move those buffers (adding or removing channels, resizing) is
// not offered: a view never outlives or loses its pixels. Arrays given to
// constructors are copied once into the library's storage.
#include <nanobind/ndarray.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <cstring>

#include "gdof/deep.h"
#include "gdof/image.h"
#include "gdof/image_set.h"
#include "gdof/metadata.h"
#include "gdof_python.h"

namespace gdof::python {

namespace {

using FloatArray3 = nb::ndarray<nb::numpy, float, nb::ndim<3>>;
using FloatArray2 = nb::ndarray<nb::numpy, float, nb::ndim<2>>;
using UIntArray2 = nb::ndarray<nb::numpy, std::uint32_t, nb::ndim<2>>;
using FloatArray1 = nb::ndarray<nb::numpy, float, nb::ndim<1>>;
using UIntArray1 = nb::ndarray<nb::numpy, std::uint32_t, nb::ndim<1>>;

PixelType parse_type(const std::string& t) {
    if (t == "half") return PixelType::Half;
    if (t == "float") return PixelType::Float;
    if (t == "uint") return PixelType::UInt;
    raise(Status::error("channel type: expected half, float or uint, got '" + t + "'", StatusCode::InvalidArgument));
}

// Channels: names ("R") or (name, type) pairs (("id", "uint")).
std::vector<ChannelSpec> to_channels(const nb::handle& h) {
    std::vector<ChannelSpec> out;
    for (nb::handle item : h) {
        if (nb::isinstance<nb::str>(item)) {
            out.push_back({nb::cast<std::string>(item), PixelType::Float});
        } else {
            auto pair = nb::cast<std::pair<std::string, std::string>>(item);
            out.push_back({pair.first, parse_type(pair.second)});
        }
    }
    return out;
}

nb::list channels_list(const std::vector<ChannelSpec>& channels) {
    nb::list l;
    for (const ChannelSpec& c : channels) l.append(nb::make_tuple(c.name, std::string(to_string(c.type))));
    return l;
}

template <class Img>
int channel_of(const Img& img, const nb::handle& which) {
    if (nb::isinstance<nb::int_>(which)) {
        const int c = nb::cast<int>(which);
        if (c < 0 || c >= img.nchannels())
            raise(Status::error("channel index " + std::to_string(c) + " out of range (" +
                                    std::to_string(img.nchannels()) + " channels)",
                                StatusCode::NotFound));
        return c;
    }
    const std::string name = nb::cast<std::string>(which);
    const int c = img.channel_index(name);
    if (c < 0) raise(Status::error("channel '" + name + "' not found", StatusCode::NotFound, "channel"));
    return c;
}

// ---- Metadata values: str, int, float, a list of numbers, a 4x4 matrix ----

nb::object attribute_value(const Attribute& a) {
    if (a.type == "string") return nb::str(a.text.c_str());
    if (a.numbers.size() == 1) {
        const bool integer = a.type == "int" || a.type == "uint" || a.type == "int64" || a.type == "uint64";
        if (integer) return nb::int_((long long)a.numbers[0]);
        return nb::float_(a.numbers[0]);
    }
    if (a.type == "matrix" && a.numbers.size() == 16) {
        nb::list rows;
        for (int r = 0; r < 4; ++r) {
            nb::list row;
            for (int c = 0; c < 4; ++c) row.append(a.numbers[std::size_t(r * 4 + c)]);
            rows.append(row);
        }
        return rows;
    }
    if (a.numbers.empty()) return nb::str(a.text.c_str());
    nb::list l;
    for (double v : a.numbers) l.append(v);
    return l;
}

void set_attribute(Metadata& md, const std::string& name, const nb::handle& value, const std::string& type) {
    Attribute a;
    a.name = name;
    if (nb::isinstance<nb::str>(value)) {
        a.type = type.empty() ? "string" : type;
        a.text = nb::cast<std::string>(value);
    } else if (nb::isinstance<nb::bool_>(value) || nb::isinstance<nb::int_>(value)) {
        a.type = type.empty() ? "int" : type;
        a.numbers = {double(nb::cast<long long>(value))};
    } else if (nb::isinstance<nb::float_>(value)) {
        a.type = type.empty() ? "float" : type;
        a.numbers = {nb::cast<double>(value)};
    } else {
        // A sequence of numbers or of rows (a matrix): flattened row-major.
        nb::object flat = nb::module_::import_("numpy").attr("asarray")(value, "float64");
        const std::size_t n = nb::cast<std::size_t>(flat.attr("size"));
        nb::object items = flat.attr("ravel")().attr("tolist")();
        for (nb::handle v : items) a.numbers.push_back(nb::cast<double>(v));
        const int ndim = nb::cast<int>(flat.attr("ndim"));
        a.type = !type.empty() ? type : (ndim == 2 && n == 16) ? "matrix" : "float[" + std::to_string(n) + "]";
    }
    md.set(std::move(a));
}

template <class Img>
nb::class_<Img>& bind_common(nb::class_<Img>& c) {
    c.def_prop_ro("channels", [](const Img& i) { return channels_list(i.channels()); },
                  "[(name, type)], type 'half', 'float' or 'uint'")
        .def_prop_ro("channel_names",
                     [](const Img& i) {
                         std::vector<std::string> n;
                         for (const ChannelSpec& s : i.channels()) n.push_back(s.name);
                         return n;
                     })
        .def("channel_index", [](const Img& i, const std::string& n) { return i.channel_index(n); },
             "index of a channel by name, -1 if absent")
        .def("set_channel_type",
             [](Img& i, const nb::handle& which, const std::string& t) { check(i.set_channel_type(channel_of(i, which), parse_type(t))); },
             "half <-> float (the storage type in files; pixels stay float32)")
        .def_prop_ro("data_window", [](const Img& i) { return i.data_window(); })
        .def_prop_rw("display_window", [](const Img& i) { return i.display_window(); },
                     [](Img& i, const nb::handle& r) { i.set_display_window(to_roi(r)); })
        .def_rw("metadata", &Img::metadata, nb::rv_policy::reference_internal)
        .def_rw("name", &Img::name, "EXR part name")
        .def_rw("view", &Img::view, "EXR view name ('left')")
        .def("copy", [](const Img& i) { return Img(i); });
    return c;
}

}  // namespace

Roi to_roi(const nb::handle& h) {
    if (nb::isinstance<Roi>(h)) return nb::cast<Roi>(h);
    std::vector<int> v = nb::cast<std::vector<int>>(h);
    if (v.size() != 4)
        raise(Status::error("a window is (x0, y0, x1, y1), got " + std::to_string(v.size()) + " numbers",
                            StatusCode::InvalidArgument));
    return {v[0], v[1], v[2], v[3]};
}

const ImageSet& to_image_set(const nb::handle& h, ImageSet& storage) {
    if (nb::isinstance<ImageSet>(h)) return *nb::inst_ptr<ImageSet>(h);
    auto add = [&](const nb::handle& part) {
        if (nb::isinstance<Image>(part)) storage.parts.emplace_back(nb::cast<const Image&>(part));
        else if (nb::isinstance<DeepImage>(part)) storage.parts.emplace_back(nb::cast<const DeepImage&>(part));
        else raise(Status::error("expected a gdof.Image, gdof.DeepImage, gdof.ImageSet or a list of images",
                                 StatusCode::InvalidArgument));
    };
    if (nb::isinstance<Image>(h) || nb::isinstance<DeepImage>(h)) add(h);
    else
        for (nb::handle part : h) add(part);
    return storage;
}

void register_images(nb::module_& m) {
    nb::class_<Roi>(m, "Roi", "A half-open pixel rectangle [x0, x1) x [y0, y1) in absolute coordinates")
        .def(nb::init<>())
        .def("__init__", [](Roi* r, int x0, int y0, int x1, int y1) { new (r) Roi{x0, y0, x1, y1}; },
             nb::arg("x0"), nb::arg("y0"), nb::arg("x1"), nb::arg("y1"))
        .def_rw("x0", &Roi::x0)
        .def_rw("y0", &Roi::y0)
        .def_rw("x1", &Roi::x1)
        .def_rw("y1", &Roi::y1)
        .def_prop_ro("width", &Roi::width)
        .def_prop_ro("height", &Roi::height)
        .def_prop_ro("empty", &Roi::empty)
        .def("__eq__", [](const Roi& a, const nb::handle& b) { return a == to_roi(b); })
        .def("__iter__", [](const Roi& r) { return nb::iter(nb::make_tuple(r.x0, r.y0, r.x1, r.y1)); })
        .def("__repr__", [](const Roi& r) {
            return "gdof.Roi(" + std::to_string(r.x0) + ", " + std::to_string(r.y0) + ", " + std::to_string(r.x1) +
                   ", " + std::to_string(r.y1) + ")";
        });

    nb::class_<Metadata>(m, "Metadata",
                         "Header attributes with their file types: md['focalLength'] -> 50.0; "
                         "md['worldToCamera'] -> 4x4 rows; md[name] = value (str, int, float, numbers, 4x4 matrix)")
        .def(nb::init<>())
        .def("__getitem__",
             [](const Metadata& md, const std::string& n) {
                 const Attribute* a = md.find(n);
                 if (!a) throw nb::key_error(n.c_str());
                 return attribute_value(*a);
             })
        .def("__setitem__", [](Metadata& md, const std::string& n, const nb::handle& v) { set_attribute(md, n, v, ""); })
        .def("set", [](Metadata& md, const std::string& n, const nb::handle& v, const std::string& type) { set_attribute(md, n, v, type); },
             nb::arg("name"), nb::arg("value"), nb::arg("type"), "set with an explicit file type ('float', 'int', 'matrix', 'float[2]', ...)")
        .def("__delitem__", [](Metadata& md, const std::string& n) {
            if (!md.has(n)) throw nb::key_error(n.c_str());
            md.erase(n);
        })
        .def("__contains__", [](const Metadata& md, const std::string& n) { return md.has(n); })
        .def("__len__", [](const Metadata& md) { return md.attributes().size(); })
        .def("keys", [](const Metadata& md) {
            std::vector<std::string> k;
            for (const Attribute& a : md.attributes()) k.push_back(a.name);
            return k;
        })
        .def("__iter__", [](const Metadata& md) {
            nb::list k;
            for (const Attribute& a : md.attributes()) k.append(a.name);
            return nb::iter(k);
        })
        .def("type", [](const Metadata& md, const std::string& n) {
            const Attribute* a = md.find(n);
            if (!a) throw nb::key_error(n.c_str());
            return a->type;
        }, "the attribute's file type")
        .def("to_dict", [](const Metadata& md) {
            nb::dict d;
            for (const Attribute& a : md.attributes()) d[a.name.c_str()] = attribute_value(a);
            return d;
        });

    nb::class_<Image> image(m, "Image",
                            "A flat image: named channels over a data window, a display window, metadata. "
                            "pixels is a (C, H, W) float32 view of the library's float planes.");
    image.def("__init__",
              [](Image* img, const nb::handle& channels, const nb::handle& data_window, const nb::handle& display_window) {
                  const Roi data = to_roi(data_window);
                  new (img) Image(to_channels(channels), data, display_window.is_none() ? data : to_roi(display_window));
              },
              nb::arg("channels"), nb::arg("data_window"), nb::arg("display_window") = nb::none(),
              "zero-filled; channels are names or (name, type) pairs")
        .def_static("from_array",
                    [](nb::ndarray<float, nb::ndim<3>, nb::c_contig, nb::device::cpu> pixels, const nb::handle& channels,
                       const nb::handle& data_window, const nb::handle& display_window) {
                        std::vector<ChannelSpec> specs = to_channels(channels);
                        const int C = int(pixels.shape(0)), H = int(pixels.shape(1)), W = int(pixels.shape(2));
                        if (int(specs.size()) != C)
                            raise(Status::error("from_array: " + std::to_string(specs.size()) + " channel names for " +
                                                    std::to_string(C) + " planes",
                                                StatusCode::InvalidArgument));
                        for (const ChannelSpec& s : specs)
                            if (s.type == PixelType::UInt)
                                raise(Status::error("from_array: channel '" + s.name + "' is uint; pixels are float32",
                                                    StatusCode::InvalidArgument));
                        const Roi data = data_window.is_none() ? Roi{0, 0, W, H} : to_roi(data_window);
                        if (data.width() != W || data.height() != H)
                            raise(Status::error("from_array: the data window " + to_string(data) + " is not the array's " +
                                                    std::to_string(W) + "x" + std::to_string(H),
                                                StatusCode::InvalidArgument));
                        Image img(std::move(specs), data, display_window.is_none() ? data : to_roi(display_window));
                        if (img.npixels() > 0)
                            std::memcpy(img.plane(0), pixels.data(), std::size_t(C) * img.npixels() * sizeof(float));
                        return img;
                    },
                    nb::arg("pixels"), nb::arg("channels"), nb::arg("data_window") = nb::none(),
                    nb::arg("display_window") = nb::none(),
                    "an image from a (C, H, W) array (copied), float channels named by `channels`")
        .def_prop_ro("width", &Image::width)
        .def_prop_ro("height", &Image::height)
        .def_prop_ro("pixels",
                     [](Image& img) {
                         // The float planes lie back to back in channel order (image.h).
                         int first = -1, n = 0;
                         for (int c = 0; c < img.nchannels(); ++c)
                             if (img.channel(c).type != PixelType::UInt) {
                                 if (first < 0) first = c;
                                 ++n;
                             }
                         const std::size_t shape[3] = {std::size_t(n), std::size_t(img.height()), std::size_t(img.width())};
                         return FloatArray3(first >= 0 && img.npixels() ? img.plane(first) : nullptr, 3, shape, nb::handle());
                     },
                     nb::rv_policy::reference_internal,
                     "(C, H, W) float32 view of the float (and half) channels, in channel order (pixel_channels); "
                     "uint channels (ids) are read with channel()")
        .def_prop_ro("pixel_channels",
                     [](const Image& img) {
                         std::vector<std::string> n;
                         for (const ChannelSpec& s : img.channels())
                             if (s.type != PixelType::UInt) n.push_back(s.name);
                         return n;
                     },
                     "the names of pixels' planes")
        .def("channel",
             [](Image& img, const nb::handle& which) -> nb::object {
                 const int c = channel_of(img, which);
                 const std::size_t shape[2] = {std::size_t(img.height()), std::size_t(img.width())};
                 nb::handle self = nb::find(&img);
                 if (img.channel(c).type == PixelType::UInt)
                     return nb::cast(UIntArray2(img.uplane(c), 2, shape, self), nb::rv_policy::reference);
                 return nb::cast(FloatArray2(img.plane(c), 2, shape, self), nb::rv_policy::reference);
             },
             nb::arg("channel"), "(H, W) view of one channel by name or index: float32, or uint32 for a uint channel")
        .def("rename_channel", [](Image& img, const nb::handle& which, const std::string& n) { img.rename_channel(channel_of(img, which), n); })
        .def("attach_depth",
             [](Image& img, const Image& depth, const nb::handle& channel, const std::string& name) {
                 // As --depth FILE: the channel named `name` in the depth image, else its first.
                 const int named = depth.channel_index(name);
                 const int c = channel.is_none() ? (named >= 0 ? named : 0) : channel_of(depth, channel);
                 if (depth.nchannels() == 0)
                     raise(Status::error("attach_depth: the depth image has no channels", StatusCode::InvalidArgument));
                 check(attach_depth(img, depth, c, name, "the plate", "the depth image"));
             },
             nb::arg("depth"), nb::arg("channel") = nb::none(), nb::arg("name") = "Z",
             "--depth FILE: puts a depth map's channel (`channel` by name or index; default the one named `name`, "
             "else the first) into this plate as channel `name` (default Z); the sizes must match")
        .def("__repr__", [](const Image& img) {
            std::string names;
            for (const ChannelSpec& s : img.channels()) names += (names.empty() ? "" : ",") + s.name;
            return "gdof.Image(" + names + ", data " + to_string(img.data_window()) + ", display " +
                   to_string(img.display_window()) + ")";
        });
    bind_common(image);

    nb::class_<DeepImage> deep(m, "DeepImage",
                               "A deep image: each pixel a list of samples; samples(c) is a view of one channel's "
                               "samples, pixel after pixel (sample_offsets gives each pixel's first)");
    deep.def("__init__",
             [](DeepImage* d, const nb::handle& channels, const nb::handle& data_window, const nb::handle& display_window,
                const nb::handle& sample_counts) {
                 const Roi data = to_roi(data_window);
                 new (d) DeepImage(to_channels(channels), data, display_window.is_none() ? data : to_roi(display_window));
                 std::vector<std::uint32_t> counts(d->npixels(), 0);
                 if (!sample_counts.is_none()) {
                     nb::object a = nb::module_::import_("numpy").attr("ascontiguousarray")(sample_counts, "uint32");
                     auto arr = nb::cast<nb::ndarray<std::uint32_t, nb::c_contig, nb::device::cpu>>(a);
                     if (arr.size() != counts.size())
                         raise(Status::error("sample_counts: " + std::to_string(arr.size()) + " values for " +
                                                 std::to_string(counts.size()) + " pixels",
                                             StatusCode::InvalidArgument));
                     std::memcpy(counts.data(), arr.data(), counts.size() * sizeof(std::uint32_t));
                 }
                 check(d->set_sample_counts(counts));
             },
             nb::arg("channels"), nb::arg("data_window"), nb::arg("display_window") = nb::none(),
             nb::arg("sample_counts") = nb::none(), "zeroed samples, `sample_counts` (H, W) per pixel (default 0)")
        .def_prop_ro("total_samples", &DeepImage::total_samples)
        .def_prop_ro("sample_counts",
                     [](const DeepImage& d) {
                         const std::size_t shape[2] = {std::size_t(d.data_window().height()), std::size_t(d.data_window().width())};
                         return nb::ndarray<nb::numpy, const std::uint32_t, nb::ndim<2>>(d.sample_counts().data(), 2, shape, nb::handle());
                     },
                     nb::rv_policy::reference_internal, "(H, W) uint32, read-only")
        .def_prop_ro("sample_offsets",
                     [](const DeepImage& d) {
                         std::vector<std::uint64_t> offsets(d.npixels());
                         for (std::size_t i = 0; i < offsets.size(); ++i) offsets[i] = d.first_sample(i);
                         return offsets;
                     },
                     "each pixel's first sample (row-major pixels), a list")
        .def("samples",
             [](DeepImage& d, const nb::handle& which) -> nb::object {
                 const int c = channel_of(d, which);
                 const std::size_t shape[1] = {d.total_samples()};
                 nb::handle self = nb::find(&d);
                 if (d.channel(c).type == PixelType::UInt)
                     return nb::cast(UIntArray1(d.usamples(c), 1, shape, self), nb::rv_policy::reference);
                 return nb::cast(FloatArray1(d.samples(c), 1, shape, self), nb::rv_policy::reference);
             },
             nb::arg("channel"), "one channel's samples, pixel after pixel: a float32 (or uint32) view")
        .def_prop_ro("z_channel", &DeepImage::z_channel)
        .def("__repr__", [](const DeepImage& d) {
            return "gdof.DeepImage(" + std::to_string(d.nchannels()) + " channels, " + std::to_string(d.total_samples()) +
                   " samples, data " + to_string(d.data_window()) + ")";
        });
    bind_common(deep);

    nb::class_<ImageSet>(m, "ImageSet",
                         "The parts of a file (EXR multipart), each a gdof.Image or gdof.DeepImage. Its parts are "
                         "references into the set (no copy); the set's structure does not change after it is made.")
        .def("__init__",
             [](ImageSet* s, const nb::handle& parts) {
                 ImageSet tmp;
                 to_image_set(parts, tmp);
                 new (s) ImageSet(std::move(tmp));
             },
             nb::arg("parts"), "a set from images (copied)")
        .def("__len__", &ImageSet::size)
        .def("__getitem__",
             [](ImageSet& s, long i) -> nb::object {
                 if (i < 0) i += long(s.size());
                 if (i < 0 || i >= long(s.size())) throw nb::index_error();
                 nb::handle self = nb::find(&s);
                 if (s.is_deep(std::size_t(i))) return nb::cast(&s.deep(std::size_t(i)), nb::rv_policy::reference_internal, self);
                 return nb::cast(&s.flat(std::size_t(i)), nb::rv_policy::reference_internal, self);
             })
        .def("is_deep", [](const ImageSet& s, std::size_t i) {
            if (i >= s.size()) throw nb::index_error();
            return s.is_deep(i);
        })
        .def("views", [](const ImageSet& s) { return part_views(s); }, "the distinct view names of the parts")
        .def("select_view", [](const ImageSet& s, const std::string& v) { return take(select_view(s, v)); },
             "the parts of one view (and those of no view), a new set")
        .def("select_parts", [](const ImageSet& s, const std::string& l) { return take(select_parts(s, l)); },
             "parts by name or index ('beauty,depth', '0,2'), a new set")
        .def("__repr__", [](const ImageSet& s) { return "gdof.ImageSet(" + std::to_string(s.size()) + " parts)"; });
}

}  // namespace gdof::python

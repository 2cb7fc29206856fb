// Reading OpenEXR files (single-part, multipart, flat and deep, scanline and
// tiled) straight through the OpenEXR C++ API, so that channel names,
// attribute names and types, and empty or odd windows come through exactly.
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <new>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfDeepFrameBuffer.h>
#include <OpenEXR/ImfDeepScanLineInputPart.h>
#include <OpenEXR/ImfDeepTiledInputPart.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputPart.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfTileDescription.h>
#include <OpenEXR/ImfTiledInputPart.h>

#include "exr/exr_attributes.h"
#include "exr/exr_common.h"
#include "exr/exr_header_check.h"
#include "exr/exr_io.h"
#include "files/files.h"

namespace gdof::io::detail {

namespace {

struct ReadError {
    std::string message;
};

Roi to_roi(const Imath::Box2i& b) { return {b.min.x, b.min.y, b.max.x + 1, b.max.y + 1}; }

PixelType to_pixel_type(Imf::PixelType t) {
    switch (t) {
        case Imf::UINT: return PixelType::UInt;
        case Imf::HALF: return PixelType::Half;
        default: return PixelType::Float;
    }
}

// Pointer arithmetic for OpenEXR's "base" convention (base + x*xs + y*ys)
// done on integers: the base itself may point outside any allocation.
char* shifted_base(const void* p, const Imath::Box2i& dw, std::size_t xs, std::size_t ys) {
    auto v = reinterpret_cast<std::intptr_t>(p);
    v -= std::intptr_t(dw.min.x) * std::intptr_t(xs) + std::intptr_t(dw.min.y) * std::intptr_t(ys);
    return reinterpret_cast<char*>(v);
}

// Channels sorted per layer: R, G, B, A first, then the rest in file order;
// layers in file (alphabetical) order with the unnamed layer first.
std::vector<ChannelSpec> ordered_channels(const Imf::ChannelList& list, const std::string& path) {
    std::vector<ChannelSpec> chans;
    for (auto it = list.begin(); it != list.end(); ++it) {
        if (it.channel().xSampling != 1 || it.channel().ySampling != 1)
            throw ReadError{quoted(path) + ": channel '" + it.name() +
                            "' is subsampled; subsampled (luminance/chroma) channels are not supported"};
        chans.push_back({it.name(), to_pixel_type(it.channel().type)});
    }
    auto layer_of = [](const std::string& n) {
        auto d = n.rfind('.');
        return d == std::string::npos ? std::string() : n.substr(0, d);
    };
    auto rank = [](const std::string& n) {
        auto d = n.rfind('.');
        std::string base = d == std::string::npos ? n : n.substr(d + 1);
        static const char* order[] = {"R", "G", "B", "A"};
        for (int i = 0; i < 4; ++i)
            if (base == order[i]) return i;
        return 4;
    };
    std::stable_sort(chans.begin(), chans.end(), [&](const ChannelSpec& a, const ChannelSpec& b) {
        std::string la = layer_of(a.name), lb = layer_of(b.name);
        if (la != lb) return la < lb;
        return rank(a.name) < rank(b.name);
    });
    return chans;
}

void check_size(std::uint64_t bytes, std::uint64_t file_size, const std::string& path, const char* what) {
    // A header that claims more is corrupt (and must not make us allocate it).
    if (bytes > decoded_bytes_limit(file_size))
        throw ReadError{quoted(path) + ": file is truncated or corrupt (" + what + " of " + std::to_string(bytes) +
                        " bytes cannot come from a file of " + std::to_string(file_size) + " bytes)"};
}

void read_flat_part(Imf::MultiPartInputFile& file, int index, Image& img) {
    const Imath::Box2i dw = file.header(index).dataWindow();
    Imf::FrameBuffer fb;
    for (int c = 0; c < img.nchannels(); ++c) {
        const auto& ch = img.channel(c);
        if (ch.type == PixelType::UInt)
            fb.insert(ch.name, Imf::Slice::Make(Imf::UINT, img.uplane(c), dw));
        else
            fb.insert(ch.name, Imf::Slice::Make(Imf::FLOAT, img.plane(c), dw));
    }
    Imf::InputPart part(file, index);
    part.setFrameBuffer(fb);
    part.readPixels(dw.min.y, dw.max.y);
}

// Deep reads: the frame buffer is set once with the sample count slice and
// one pointer array per channel; the pointers are filled in once the counts
// are known (setting the frame buffer again would forget the counts).
template <class PartT, class ReadCounts, class ReadPixels>
void read_deep_generic(PartT& part, DeepImage& img, const Imath::Box2i& dw, std::uint64_t file_size,
                       const std::string& path, ReadCounts read_counts, ReadPixels read_pixels) {
    const std::size_t w = std::size_t(img.data_window().width());
    const std::size_t np = img.npixels();
    const std::size_t nch = std::size_t(img.nchannels());
    std::vector<std::uint32_t> counts(np, 0u);
    std::vector<std::vector<char*>> ptrs(nch, std::vector<char*>(np, nullptr));
    Imf::DeepFrameBuffer fb;
    fb.insertSampleCountSlice(Imf::Slice(Imf::UINT, shifted_base(counts.data(), dw, 4, 4 * w), 4, 4 * w));
    for (std::size_t c = 0; c < nch; ++c) {
        const bool is_uint = img.channel(int(c)).type == PixelType::UInt;
        fb.insert(img.channel(int(c)).name,
                  Imf::DeepSlice(is_uint ? Imf::UINT : Imf::FLOAT,
                                 shifted_base(ptrs[c].data(), dw, sizeof(char*), sizeof(char*) * w), sizeof(char*),
                                 sizeof(char*) * w, 4));
    }
    part.setFrameBuffer(fb);
    read_counts(part);
    std::uint64_t total = 0;
    for (auto n : counts) total += n;
    check_size(total * std::uint64_t(std::max<std::size_t>(1, nch)) * 4u, file_size, path, "deep samples");
    if (Status st = img.set_sample_counts(counts); !st) throw ReadError{quoted(path) + ": " + st.message()};
    for (std::size_t c = 0; c < nch; ++c) {
        const bool is_uint = img.channel(int(c)).type == PixelType::UInt;
        char* base = is_uint ? reinterpret_cast<char*>(img.usamples(int(c))) : reinterpret_cast<char*>(img.samples(int(c)));
        for (std::size_t p = 0; p < np; ++p) ptrs[c][p] = counts[p] ? base + img.first_sample(p) * 4 : nullptr;
    }
    read_pixels(part);
}

void read_deep_part(Imf::MultiPartInputFile& file, int index, DeepImage& img, std::uint64_t file_size,
                    const std::string& path) {
    const Imf::Header& h = file.header(index);
    const Imath::Box2i dw = h.dataWindow();
    if (h.type() == Imf::DEEPTILE) {
        Imf::DeepTiledInputPart part(file, index);
        read_deep_generic(
            part, img, dw, file_size, path,
            [](Imf::DeepTiledInputPart& p) { p.readPixelSampleCounts(0, p.numXTiles(0) - 1, 0, p.numYTiles(0) - 1); },
            [](Imf::DeepTiledInputPart& p) { p.readTiles(0, p.numXTiles(0) - 1, 0, p.numYTiles(0) - 1); });
    } else {
        Imf::DeepScanLineInputPart part(file, index);
        read_deep_generic(
            part, img, dw, file_size, path,
            [&](Imf::DeepScanLineInputPart& p) { p.readPixelSampleCounts(dw.min.y, dw.max.y); },
            [&](Imf::DeepScanLineInputPart& p) { p.readPixels(dw.min.y, dw.max.y); });
    }
}

Part read_part(Imf::MultiPartInputFile& file, int index, std::uint64_t file_size, const std::string& path) {
    const Imf::Header& h = file.header(index);
    const bool tiled_desc = h.hasTileDescription();
    std::string type = h.hasType() ? h.type() : (tiled_desc ? Imf::TILEDIMAGE : Imf::SCANLINEIMAGE);
    const bool deep = Imf::isDeepData(type);

    std::vector<ChannelSpec> chans = ordered_channels(h.channels(), path);
    Roi data = to_roi(h.dataWindow());
    Roi display = to_roi(h.displayWindow());

    Metadata md;
    exr_header_to_metadata(h, md);
    StorageHints hints;
    hints.format = "openexr";
    hints.compression = compression_name(h.compression());
    if (tiled_desc) {
        hints.tile_width = int(h.tileDescription().xSize);
        hints.tile_height = int(h.tileDescription().ySize);
    }
    const bool empty_window = h.find(kEmptyDataWindowAttr) != h.end();
    if (empty_window) data = {data.x0, data.y0, data.x0, data.y0};
    check_size(std::uint64_t(data.npixels()) * std::uint64_t(chans.size()) * 4u, file_size, path, "pixel data");

    std::string name = h.hasName() ? h.name() : std::string();
    std::string view = h.hasView() ? h.view() : std::string();

    if (deep) {
        DeepImage img(chans, data, display);
        if (!empty_window) read_deep_part(file, index, img, file_size, path);
        img.metadata = std::move(md);
        img.storage = std::move(hints);
        img.name = std::move(name);
        img.view = std::move(view);
        return img;
    }
    Image img(chans, data, display);
    if (!empty_window) read_flat_part(file, index, img);
    img.metadata = std::move(md);
    img.storage = std::move(hints);
    img.name = std::move(name);
    img.view = std::move(view);
    return img;
}

}  // namespace

Result<ImageSet> read_exr(const std::string& path) {
    std::error_code ec;
    const std::uint64_t file_size = std::filesystem::file_size(path, ec);
    if (ec) return Status::error(quoted(path) + ": cannot read (" + ec.message() + ")");
    if (Status st = check_exr_header_sizes(path, file_size); !st) return st;
    try {
        ensure_exr_setup();
        const ExrThreads threads;  // outlives the file
        Imf::MultiPartInputFile file(path.c_str(), exr_thread_count());
        ImageSet set;
        const int n = file.parts();
        if (n <= 0) return Status::error(quoted(path) + ": file is truncated or corrupt (no parts)");
        set.parts.reserve(std::size_t(n));
        for (int i = 0; i < n; ++i) set.parts.push_back(read_part(file, i, file_size, path));
        return set;
    } catch (const ReadError& e) {
        return Status::error(e.message);
    } catch (const std::bad_alloc&) {
        return Status::error(quoted(path) + ": file is truncated or corrupt (out of memory while reading)");
    } catch (const std::exception& e) {
        return Status::error(quoted(path) + ": file is truncated or corrupt (OpenEXR: " + e.what() + ")");
    } catch (...) {
        return Status::error(quoted(path) + ": file is truncated or corrupt (unknown OpenEXR error)");
    }
}

}  // namespace gdof::io::detail

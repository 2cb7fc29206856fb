// Writing OpenEXR files: one part per ImageSet part, flat or deep, scanline
// or tiled per StorageHints, channel types kept, all metadata attributes.
#include <cstdint>
#include <memory>
#include <optional>
#include <set>

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfDeepFrameBuffer.h>
#include <OpenEXR/ImfDeepScanLineOutputPart.h>
#include <OpenEXR/ImfDeepTiledOutputPart.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfMultiPartOutputFile.h>
#include <OpenEXR/ImfOutputPart.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfTileDescription.h>
#include <OpenEXR/ImfTiledOutputPart.h>

#include "exr/exr_attributes.h"
#include "exr/exr_common.h"
#include "exr/exr_io.h"
#include "exr/exr_ostream.h"
#include "files/files.h"

namespace gdof::io::detail {

namespace {

struct WriteError {
    std::string message;
};

Imath::Box2i to_box(const Roi& r) { return Imath::Box2i(Imath::V2i(r.x0, r.y0), Imath::V2i(r.x1 - 1, r.y1 - 1)); }

const char* shifted_base(const void* p, const Imath::Box2i& dw, std::size_t xs, std::size_t ys) {
    auto v = reinterpret_cast<std::intptr_t>(p);
    v -= std::intptr_t(dw.min.x) * std::intptr_t(xs) + std::intptr_t(dw.min.y) * std::intptr_t(ys);
    return reinterpret_cast<const char*>(v);
}

// What each part needs beyond its header.
struct PartPlan {
    bool deep = false;
    bool tiled = false;
    bool empty = false;  // written as one placeholder pixel
    Imath::Box2i dw;
    std::vector<Imf::PixelType> types;  // file type per channel (image order)
};

// OpenEXR converts pixel types on input only: half channels are converted here.
std::vector<Imath::half> to_half(const float* p, std::size_t n) {
    std::vector<Imath::half> h(n);
    for (std::size_t i = 0; i < n; ++i) h[i] = Imath::half(p[i]);
    return h;
}

struct PartView {
    const std::vector<ChannelSpec>* channels;
    Roi data, display;
    const Metadata* metadata;
    const StorageHints* storage;
    const std::string* name;
    const std::string* view;
    bool deep;
};

PartView view_of(const PartRef& p) {
    return std::visit(
        [](const auto* ptr) {
            const auto& img = *ptr;
            using T = std::decay_t<decltype(img)>;
            return PartView{&img.channels(), img.data_window(), img.display_window(), &img.metadata,
                            &img.storage,    &img.name,         &img.view,           std::is_same_v<T, DeepImage>};
        },
        p);
}

Imf::Header make_header(const PartView& pv, std::size_t index, bool multipart, const WriteOptions& opts,
                        const std::string& display, PartPlan& plan) {
    const std::string where = quoted(display) + (multipart ? ": part " + std::to_string(index) : std::string());
    plan.deep = pv.deep;
    plan.empty = pv.data.empty();
    Roi data = plan.empty ? Roi{pv.data.x0, pv.data.y0, pv.data.x0 + 1, pv.data.y0 + 1} : pv.data;
    Roi disp = pv.display.empty() ? data : pv.display;
    plan.dw = to_box(data);

    Imf::Header h(to_box(disp), plan.dw);

    // Channels.
    if (pv.channels->empty()) throw WriteError{where + ": image has no channels"};
    std::set<std::string> seen;
    for (const auto& ch : *pv.channels) {
        if (ch.name.empty()) throw WriteError{where + ": a channel has an empty name"};
        if (!seen.insert(ch.name).second) throw WriteError{where + ": channel '" + ch.name + "' appears twice"};
        Imf::PixelType t = Imf::FLOAT;
        if (ch.type == PixelType::UInt) t = Imf::UINT;
        else if (opts.pixel_type == "half") t = Imf::HALF;
        else if (opts.pixel_type == "float") t = Imf::FLOAT;
        else if (opts.pixel_type.empty()) t = ch.type == PixelType::Half ? Imf::HALF : Imf::FLOAT;
        else throw WriteError{quoted(display) + ": unknown pixel type '" + opts.pixel_type + "' (use half or float)"};
        h.channels().insert(ch.name, Imf::Channel(t));
        plan.types.push_back(t);
    }

    // Compression.
    Imf::Compression comp = pv.deep ? Imf::ZIPS_COMPRESSION : Imf::ZIP_COMPRESSION;
    double level = -1;
    if (!opts.compression.empty()) {
        if (!parse_compression(opts.compression, comp, level))
            throw WriteError{quoted(display) + ": unknown EXR compression '" + opts.compression +
                             "' (none, rle, zips, zip, piz, pxr24, b44, b44a, dwaa, dwab)"};
    } else if (!pv.storage->compression.empty()) {
        Imf::Compression c;
        double l;
        if (parse_compression(pv.storage->compression, c, l)) comp = c, level = l;  // else a foreign name: default
    }
    if (pv.deep && comp != Imf::NO_COMPRESSION && comp != Imf::RLE_COMPRESSION && comp != Imf::ZIPS_COMPRESSION &&
        comp != Imf::ZIP_COMPRESSION)
        comp = Imf::ZIPS_COMPRESSION;  // deep data allows only these
    h.compression() = comp;
    if (level >= 0 && (comp == Imf::ZIP_COMPRESSION || comp == Imf::ZIPS_COMPRESSION))
        h.zipCompressionLevel() = int(level);
    if (level >= 0 && (comp == Imf::DWAA_COMPRESSION || comp == Imf::DWAB_COMPRESSION))
        h.dwaCompressionLevel() = float(level);

    // Layout.
    plan.tiled = pv.storage->tile_width > 0 && pv.storage->tile_height > 0;
    if (plan.tiled)
        h.setTileDescription(Imf::TileDescription(unsigned(pv.storage->tile_width),
                                                  unsigned(pv.storage->tile_height), Imf::ONE_LEVEL));
    h.setType(pv.deep ? (plan.tiled ? Imf::DEEPTILE : Imf::DEEPSCANLINE)
                      : (plan.tiled ? Imf::TILEDIMAGE : Imf::SCANLINEIMAGE));

    metadata_to_exr_header(*pv.metadata, h);
    if (plan.empty) h.insert(kEmptyDataWindowAttr, Imf::IntAttribute(1));
    if (!pv.view->empty()) h.setView(*pv.view);
    return h;
}

// Writes a part's whole frame buffer: all its tiles, or all its scanlines.
template <class TiledPart, class ScanLinePart, class FrameBuffer>
void write_part(Imf::MultiPartOutputFile& out, int index, const FrameBuffer& fb, const PartPlan& plan) {
    if (plan.tiled) {
        TiledPart part(out, index);
        part.setFrameBuffer(fb);
        part.writeTiles(0, part.numXTiles(0) - 1, 0, part.numYTiles(0) - 1);
    } else {
        ScanLinePart part(out, index);
        part.setFrameBuffer(fb);
        part.writePixels(plan.dw.max.y - plan.dw.min.y + 1);
    }
}

void write_flat(Imf::MultiPartOutputFile& out, int index, const Image& img, const PartPlan& plan) {
    Imf::FrameBuffer fb;
    const std::size_t nch = std::size_t(img.nchannels());
    const std::vector<float> zero_f(nch, 0.0f);
    const std::vector<std::uint32_t> zero_u(nch, 0u);
    std::vector<std::vector<Imath::half>> halves(nch);
    for (std::size_t c = 0; c < nch; ++c) {
        const auto& ch = img.channel(int(c));
        const Imf::PixelType t = plan.types[c];
        const void* p = nullptr;
        if (t == Imf::UINT) p = plan.empty ? &zero_u[c] : static_cast<const void*>(img.uplane(int(c)));
        else {
            const float* f = plan.empty ? &zero_f[c] : img.plane(int(c));
            if (t == Imf::HALF) {
                halves[c] = to_half(f, plan.empty ? 1 : img.npixels());
                p = halves[c].data();
            } else {
                p = f;
            }
        }
        fb.insert(ch.name, Imf::Slice::Make(t, p, plan.dw));
    }
    write_part<Imf::TiledOutputPart, Imf::OutputPart>(out, index, fb, plan);
}

void write_deep(Imf::MultiPartOutputFile& out, int index, const DeepImage& img, const PartPlan& plan) {
    const std::size_t w = std::size_t(plan.dw.max.x - plan.dw.min.x + 1);
    const std::size_t np = plan.empty ? 1 : img.npixels();
    std::vector<std::uint32_t> counts = plan.empty ? std::vector<std::uint32_t>(1, 0u) : img.sample_counts();
    Imf::DeepFrameBuffer fb;
    fb.insertSampleCountSlice(Imf::Slice(Imf::UINT, const_cast<char*>(shifted_base(counts.data(), plan.dw, 4, 4 * w)),
                                         4, 4 * w));
    std::vector<std::vector<const char*>> ptrs(std::size_t(img.nchannels()));
    std::vector<std::vector<Imath::half>> halves(std::size_t(img.nchannels()));
    for (int c = 0; c < img.nchannels(); ++c) {
        const Imf::PixelType t = plan.types[std::size_t(c)];
        const std::size_t es = t == Imf::HALF ? 2 : 4;
        auto& pc = ptrs[std::size_t(c)];
        pc.assign(np, nullptr);
        if (!plan.empty && img.total_samples() > 0) {
            const char* base = nullptr;
            if (t == Imf::UINT) base = reinterpret_cast<const char*>(img.usamples(c));
            else if (t == Imf::FLOAT) base = reinterpret_cast<const char*>(img.samples(c));
            else {
                halves[std::size_t(c)] = to_half(img.samples(c), img.total_samples());
                base = reinterpret_cast<const char*>(halves[std::size_t(c)].data());
            }
            for (std::size_t p = 0; p < np; ++p)
                if (counts[p]) pc[p] = base + img.first_sample(p) * es;
        }
        fb.insert(img.channel(c).name,
                  Imf::DeepSlice(t, const_cast<char*>(shifted_base(pc.data(), plan.dw, sizeof(char*), sizeof(char*) * w)),
                                 sizeof(char*), sizeof(char*) * w, es));
    }
    write_part<Imf::DeepTiledOutputPart, Imf::DeepScanLineOutputPart>(out, index, fb, plan);
}

}  // namespace

std::vector<PartRef> part_refs(const ImageSet& images) {
    std::vector<PartRef> refs;
    for (const auto& p : images.parts) {
        if (const auto* img = std::get_if<Image>(&p)) refs.emplace_back(img);
        else refs.emplace_back(&std::get<DeepImage>(p));
    }
    return refs;
}

Status write_exr(const std::string& file, const std::string& display, const std::vector<PartRef>& images,
                 const WriteOptions& opts) {
    // The stream outlives the OpenEXR file, whose destructor still writes.
    std::optional<CheckedOStream> stream;
    try {
        ensure_exr_setup();
        const ExrThreads threads;  // outlives the file
        const std::size_t n = images.size();
        bool multipart = n > 1;
        for (const auto& p : images)
            if (!view_of(p).name->empty()) multipart = true;
        std::vector<Imf::Header> headers;
        std::vector<PartPlan> plans(n);
        std::set<std::string> names;
        for (std::size_t i = 0; i < n; ++i) {
            PartView pv = view_of(images[i]);
            headers.push_back(make_header(pv, i, multipart, opts, display, plans[i]));
            if (i > 0 && headers[i].displayWindow() != headers[0].displayWindow())
                throw WriteError{quoted(display) + ": part " + std::to_string(i) + " has display window " +
                                 to_string(pv.display) + " but part 0 has " + to_string(view_of(images[0]).display) +
                                 "; the parts of a multipart EXR share one display window"};
            if (multipart) {
                std::string name = pv.name->empty() ? "part" + std::to_string(i) : *pv.name;
                if (!names.insert(name).second)
                    throw WriteError{quoted(display) + ": part " + std::to_string(i) + ": part name '" + name +
                                     "' is used twice (EXR part names must be unique)"};
                headers.back().setName(name);
            }
        }
        stream.emplace(file, display);
        {
            Imf::MultiPartOutputFile out(*stream, headers.data(), int(n), false, exr_thread_count());
            for (std::size_t i = 0; i < n; ++i) {
                if (plans[i].deep) write_deep(out, int(i), *std::get<const DeepImage*>(images[i]), plans[i]);
                else write_flat(out, int(i), *std::get<const Image*>(images[i]), plans[i]);
            }
        }
        if (std::string e = stream->finish(); !e.empty()) return Status::error(e, StatusCode::Io);
        return Status::ok();
    } catch (const WriteError& e) {
        return Status::error(e.message);
    } catch (const std::bad_alloc&) {
        return Status::error(quoted(display) + ": cannot write (out of memory)");
    } catch (const std::exception& e) {
        // A file-system error (full disk, file too large) says so itself.
        if (stream)
            if (std::string se = stream->finish(); !se.empty()) return Status::error(se, StatusCode::Io);
        return Status::error(quoted(display) + ": cannot write (OpenEXR: " + std::string(e.what()) + ")");
    } catch (...) {
        return Status::error(quoted(display) + ": cannot write (unknown OpenEXR error)");
    }
}

}  // namespace gdof::io::detail

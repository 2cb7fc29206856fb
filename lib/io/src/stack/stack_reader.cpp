// StackReader (stack_reader.h): reference tiles through the OIIO module's
// ImageCache (oiio/oiio_io.h), opened lazily, checked for size, linearised
// like read_image.
#include "gdof/io/stack_reader.h"

#include <OpenEXR/ImfInputFile.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <mutex>
#include <vector>

#include "exr/exr_attributes.h"
#include "colour/linearize.h"
#include "files/files.h"
#include "oiio/oiio_io.h"

namespace gdof::io {

namespace {

std::string size_str(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

// Simple header attributes of a non-EXR file (numbers and strings).
void simple_attributes(const Metadata& all, Metadata& md) {
    for (const Attribute& a : all.attributes()) {
        if (a.name.rfind("oiio:", 0) == 0 || a.name == "compression") continue;
        if (a.type == "string") md.set_string(a.name, a.text);
        else if ((a.type == "float" || a.type == "double") && a.numbers.size() == 1) md.set_float(a.name, a.numbers[0]);
        else if (a.type == "int" && a.numbers.size() == 1) md.set_int(a.name, (long long)a.numbers[0]);
    }
}

}  // namespace

struct StackReader::Impl {
    FocalStack stack;
    StackReaderOptions opts;
    const detail::OiioModuleApi* oiio = nullptr;

    struct Ref {
        bool opened = false;
        Status status;          // the open's result (kept: errors repeat)
        std::string name;       // the file, as the cache knows it
        Roi dw;                 // file data window
        int ch[4] = {-1, -1, -1, -1};
        int chbegin = 0, chend = 0;
        bool grey = false;
        std::string space;      // colour space to convert from ("" = none)
        bool straight_alpha = false;
        bool exr = false;
    };
    std::vector<Ref> refs;
    std::mutex mu;
    // The stack's size and data window origin, once known.
    int width = 0, height = 0;
    bool have_origin = false;
    int ox = 0, oy = 0;
    int first_ref = -1;
    std::atomic<int> opened{0};
    int unique_files_at_start = 0;  // the shared cache's count when this reader was made

    std::string where(int i) const {
        return "reference '" + stack.references[std::size_t(i)].path + "' (references[" + std::to_string(i) + "])";
    }

    // Reference i, opened (under `mu`), as a copy to read from without the lock.
    Result<Ref> opened_ref(int i) {
        if (i < 0 || i >= int(refs.size())) return Status::error("reference " + std::to_string(i) + " out of range");
        std::lock_guard<std::mutex> lock(mu);
        if (Status s = open(i); !s) return s;
        return refs[std::size_t(i)];
    }

    // Opens reference i under `mu`.
    Status open(int i) {
        Ref& r = refs[std::size_t(i)];
        if (r.opened) return r.status;
        r.opened = true;
        ++opened;
        const std::string& path = stack.references[std::size_t(i)].path;
        std::error_code ec;
        if (!std::filesystem::exists(path, ec)) return r.status = Status::error(where(i) + ": file not found");
        r.name = path;
        const Result<detail::OiioHeader> header = oiio->cache_header(r.name);
        if (!header) return r.status = Status::error(where(i) + ": cannot read: " + header.status().message());
        const detail::OiioHeader* spec = &header.value();
        if (spec->deep) return r.status = Status::error(where(i) + ": is a deep image; a stack reference must be flat");
        r.dw = spec->data;
        // Size against the stack.
        if (width == 0) {
            width = r.dw.width();
            height = r.dw.height();
        }
        if (r.dw.width() != width || r.dw.height() != height) {
            const std::string against = first_ref >= 0 ? "reference '" + stack.references[std::size_t(first_ref)].path + "'"
                                                        : std::string("the manifest's width/height");
            return r.status = Status::error(where(i) + " is " + size_str(r.dw.width(), r.dw.height()) + " but " + against +
                                            " is " + size_str(width, height) + " (all references must have one resolution)");
        }
        if (!have_origin) {
            have_origin = true;
            ox = r.dw.x0;
            oy = r.dw.y0;
        } else if (r.dw.x0 != ox || r.dw.y0 != oy) {
            return r.status = Status::error(where(i) + ": data window origin (" + std::to_string(r.dw.x0) + ", " +
                                            std::to_string(r.dw.y0) + ") differs from the other references' (" +
                                            std::to_string(ox) + ", " + std::to_string(oy) + ")");
        }
        if (first_ref < 0) first_ref = i;
        // Channels.
        const int n = int(spec->channels.size());
        auto find = [&](std::initializer_list<const char*> names) {
            for (int c = 0; c < n; ++c) {
                const std::string cn = detail::lower(spec->channels[std::size_t(c)]);
                for (const char* want : names)
                    if (cn == want) return c;
            }
            return -1;
        };
        r.ch[0] = find({"r", "red"});
        r.ch[1] = find({"g", "green"});
        r.ch[2] = find({"b", "blue"});
        r.ch[3] = find({"a", "alpha"});
        if (r.ch[3] < 0 && spec->alpha_channel >= 0) r.ch[3] = spec->alpha_channel;
        if (r.ch[0] < 0 && r.ch[1] < 0 && r.ch[2] < 0) {
            if (n == 1 || (n == 2 && r.ch[3] >= 0)) {
                r.grey = true;
                r.ch[0] = r.ch[1] = r.ch[2] = (r.ch[3] == 0 ? 1 : 0);
            } else if (n >= 3) {
                r.ch[0] = 0, r.ch[1] = 1, r.ch[2] = 2;
            }
        }
        int lo = n, hi = -1;
        for (int c : r.ch)
            if (c >= 0) lo = std::min(lo, c), hi = std::max(hi, c);
        if (hi < 0) return r.status = Status::error(where(i) + ": no R, G, B or A channel");
        r.chbegin = lo;
        r.chend = hi + 1;
        // Colour space, as read_image decides it.
        r.exr = detail::has_exr_magic(path);
        if (opts.linearize) {
            const ColourConfig& config = detail::config_or_default(opts.colour);
            std::string space = opts.colorspace;
            if (space.empty() && !r.exr) {
                const std::string& cs = spec->colorspace;
                if (!cs.empty() && !config.resolve(cs).empty()) space = cs;
                else space = spec->floating_point ? "linear" : "sRGB";
            }
            if (!space.empty()) {
                if (config.resolve(space).empty())
                    return r.status = Status::error(where(i) + ": unknown colour space '" + space + "'");
                if (!config.is_linear(space)) r.space = space;
            }
            r.straight_alpha = !r.exr && r.ch[3] >= 0 && spec->unassociated_alpha;
        }
        return r.status = Status::ok();
    }
};

Result<std::unique_ptr<StackReader>> StackReader::create(const FocalStack& stack, const StackReaderOptions& opts) {
    if (stack.references.empty()) return Status::error("the stack has no references");
    std::unique_ptr<StackReader> r(new StackReader());
    r->impl_ = std::make_unique<Impl>();
    Impl& m = *r->impl_;
    m.stack = stack;
    m.opts = opts;
    m.refs.resize(stack.references.size());
    m.width = stack.width > 0 && stack.height > 0 ? stack.width : 0;
    m.height = stack.width > 0 && stack.height > 0 ? stack.height : 0;
    const auto oiio = detail::oiio_module();
    if (!oiio) {
        Status s = oiio.status();
        return s.prefix("reading the stack's references");
    }
    m.oiio = *oiio;
    // Process-wide settings: the last reader created sets them.
    m.oiio->cache_configure(std::max(16.0, opts.cache_memory_mb), std::max(8, opts.cache_tile));
    m.unique_files_at_start = m.oiio->cache_files_opened();
    return r;
}

StackReader::~StackReader() {
    if (!impl_ || !impl_->oiio) return;
    // Release this reader's tiles and file handles from the shared cache.
    for (const Impl::Ref& r : impl_->refs)
        if (r.opened && !r.name.empty()) impl_->oiio->cache_release(r.name);
}

int StackReader::size() const { return int(impl_->refs.size()); }
int StackReader::files_opened() const { return impl_->opened.load(); }
int StackReader::cache_files_opened() const {
    return impl_->oiio->cache_files_opened() - impl_->unique_files_at_start;
}

Result<ReferenceInfo> StackReader::info(int i) {
    Impl& m = *impl_;
    const Result<Impl::Ref> opened = m.opened_ref(i);
    if (!opened) return opened.status();
    const Impl::Ref& r = *opened;
    const Result<detail::OiioHeader> spec = m.oiio->cache_header(r.name);
    if (!spec) return Status::error(m.where(i) + ": cannot read: " + spec.status().message());
    ReferenceInfo info;
    info.data_window = r.dw;
    info.display_window = spec->display;
    if (r.exr) {
        try {
            Imf::InputFile file(m.stack.references[std::size_t(i)].path.c_str());
            detail::exr_header_to_metadata(file.header(), info.metadata);
        } catch (const std::exception& e) {
            return Status::error(m.where(i) + ": reading the header: " + e.what());
        }
    } else {
        simple_attributes(spec->attributes, info.metadata);
    }
    return info;
}

Status StackReader::read_tile(int i, const Roi& tile, float* rgba) {
    Impl& m = *impl_;
    const Result<Impl::Ref> opened = m.opened_ref(i);
    if (!opened) return opened.status();
    const Impl::Ref& r = *opened;
    if (tile.empty()) return Status::ok();
    if (tile.x0 < 0 || tile.y0 < 0 || tile.x1 > r.dw.width() || tile.y1 > r.dw.height())
        return Status::error(m.where(i) + ": tile " + to_string(tile) + " is outside the image");
    const int nch = r.chend - r.chbegin;
    const std::size_t np = tile.npixels();
    thread_local std::vector<float> buf;
    buf.resize(np * std::size_t(nch));
    const Roi pixels{r.dw.x0 + tile.x0, r.dw.y0 + tile.y0, r.dw.x0 + tile.x1, r.dw.y0 + tile.y1};
    if (Status st = m.oiio->cache_read(r.name, pixels, r.chbegin, r.chend, buf.data()); !st)
        return Status::error(m.where(i) + ": reading pixels " + to_string(tile) + ": " + st.message());
    for (std::size_t p = 0; p < np; ++p) {
        const float* src = &buf[p * std::size_t(nch)];
        float* dst = rgba + p * 4;
        for (int c = 0; c < 3; ++c) dst[c] = r.ch[c] >= 0 ? src[r.ch[c] - r.chbegin] : 0.0f;
        dst[3] = r.ch[3] >= 0 ? src[r.ch[3] - r.chbegin] : 1.0f;
    }
    if (!r.space.empty()) {
        thread_local std::vector<float> planes;
        planes.resize(np * 3);
        float* pr = planes.data();
        float* pg = pr + np;
        float* pb = pg + np;
        for (std::size_t p = 0; p < np; ++p) pr[p] = rgba[p * 4], pg[p] = rgba[p * 4 + 1], pb[p] = rgba[p * 4 + 2];
        const ColourConfig& config = detail::config_or_default(m.opts.colour);
        if (Status s = config.convert_planes(pr, pg, pb, np, r.space, detail::kWorkingSpace); !s)
            return s.prefix(m.where(i));
        for (std::size_t p = 0; p < np; ++p) rgba[p * 4] = pr[p], rgba[p * 4 + 1] = pg[p], rgba[p * 4 + 2] = pb[p];
    }
    if (r.straight_alpha)
        for (std::size_t p = 0; p < np; ++p)
            for (int c = 0; c < 3; ++c) rgba[p * 4 + std::size_t(c)] *= rgba[p * 4 + 3];
    return Status::ok();
}

Status check_stack_files(const FocalStack& stack) {
    // The first reference's size, or the manifest's, and whose it is.
    int width = stack.width, height = stack.height;
    std::string against = "the manifest's width/height";
    for (std::size_t i = 0; i < stack.references.size(); ++i) {
        const StackReference& r = stack.references[i];
        const std::string where = "reference '" + r.path + "' (references[" + std::to_string(i) + "]";
        std::error_code ec;
        if (!std::filesystem::exists(r.path, ec)) return Status::error(where + ", \"file\": \"" + r.file + "\"): file not found");
        if (std::filesystem::is_directory(r.path, ec)) return Status::error(where + "): is a folder");
        // The header only: a reference of another size would otherwise be
        // found only if a pixel picks it.
        const Result<detail::OiioHeader> spec = detail::read_oiio_header(r.path);
        if (!spec) return Status::error(where + "): cannot read: " + spec.status().message());
        const int w = spec->data.width(), h = spec->data.height();
        if (width <= 0 || height <= 0) {
            width = w;
            height = h;
            against = "reference '" + r.path + "'";
        } else if (w != width || h != height) {
            return Status::error(where + ") is " + size_str(w, h) + " but " + against + " is " +
                                 size_str(width, height) + " (all references must have one resolution)");
        }
    }
    return Status::ok();
}

}  // namespace gdof::io

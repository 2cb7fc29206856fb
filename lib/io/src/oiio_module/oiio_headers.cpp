// Headers (ImageInput) and the process's one ImageCache, which the stack
// reader (io_stack) reads references through tile by tile.
#include <OpenImageIO/imagecache.h>

#include "oiio_module/oiio_module.h"

namespace gdof::io::oiio_module {

namespace {

OiioHeader header_of(const OIIO::ImageSpec& spec) {
    OiioHeader h;
    h.data = {spec.x, spec.y, spec.x + spec.width, spec.y + spec.height};
    h.display = {spec.full_x, spec.full_y, spec.full_x + spec.full_width, spec.full_y + spec.full_height};
    for (int c = 0; c < spec.nchannels; ++c)
        h.channels.push_back(c < int(spec.channelnames.size()) ? spec.channelnames[std::size_t(c)]
                                                               : "channel" + std::to_string(c));
    h.alpha_channel = spec.alpha_channel;
    h.deep = spec.deep;
    h.floating_point = spec.format.is_floating_point();
    h.unassociated_alpha = spec.get_int_attribute("oiio:UnassociatedAlpha", 0) != 0;
    h.colorspace = spec.get_string_attribute("oiio:ColorSpace");
    spec_to_metadata(spec, h.attributes);
    return h;
}

// One ImageCache for the process, created on first use and never
// destroyed. Creating and destroying private caches while TBB worker threads
// keep OIIO's per-thread cache records corrupts the heap (seen with OIIO
// 2.4: a second reader after a first one was destroyed), so the stack
// readers share this one and release their files with invalidate().
OIIO::ImageCache* cache() {
    static OIIO::ImageCache* c = [] {
        OIIO::ImageCache* ic = OIIO::ImageCache::create(/*shared=*/false);
        if (ic) {
            ic->attribute("autoscanline", 1);
            ic->attribute("unassociatedalpha", 1);  // straight colour is linearised before premultiplying
            ic->attribute("max_open_files", 64);
        }
        return ic;
    }();
    return c;
}

Status no_cache() { return Status::error("cannot create an OpenImageIO image cache"); }

}  // namespace

Result<OiioHeader> header(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        const std::string e = OIIO::geterror();
        return Status::error(e.empty() ? "unknown error" : e);
    }
    OiioHeader h = header_of(in->spec());
    in->close();
    return h;
}

void cache_configure(double max_memory_mb, int strip_rows) {
    if (OIIO::ImageCache* c = cache()) {
        c->attribute("max_memory_MB", float(max_memory_mb));
        c->attribute("autotile", strip_rows);
    }
}

int cache_files_opened() {
    int n = 0;
    if (OIIO::ImageCache* c = cache()) c->getattribute("stat:unique_files", n);
    return n;
}

Result<OiioHeader> cache_header(const std::string& path) {
    OIIO::ImageCache* c = cache();
    if (!c) return no_cache();
    const OIIO::ImageSpec* spec = c->imagespec(OIIO::ustring(path));
    if (!spec) {
        const std::string e = c->geterror();
        return Status::error(e.empty() ? "unknown error" : e);
    }
    return header_of(*spec);
}

Status cache_read(const std::string& path, const Roi& p, int chbegin, int chend, float* out) {
    OIIO::ImageCache* c = cache();
    if (!c) return no_cache();
    if (!c->get_pixels(OIIO::ustring(path), 0, 0, p.x0, p.x1, p.y0, p.y1, 0, 1, chbegin, chend, OIIO::TypeFloat, out,
                       OIIO::AutoStride, OIIO::AutoStride, OIIO::AutoStride, chbegin, chend)) {
        const std::string e = c->geterror();
        return Status::error(e.empty() ? "failed" : e);
    }
    return Status::ok();
}

void cache_release(const std::string& path) {
    if (OIIO::ImageCache* c = cache()) c->invalidate(OIIO::ustring(path), true);
}

}  // namespace gdof::io::oiio_module

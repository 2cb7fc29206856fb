// The module's one exported symbol: the table of its functions, with what
// the loader checks it against (oiio_module_api.h).
#include "oiio_module/oiio_module.h"

namespace gdof::io::oiio_module {
namespace {

detail::OiioModuleApi make_api() {
    detail::OiioModuleApi api;
    api.version = GDOF_VERSION_STRING;
    api.sizes[0] = sizeof(ImageSet);
    api.sizes[1] = sizeof(Image);
    api.sizes[2] = sizeof(Metadata);
    api.sizes[3] = sizeof(WriteOptions);
    api.read = &read;
    api.write = &write;
    api.clear_error = &clear_error;
    api.header = &header;
    api.cache_configure = &cache_configure;
    api.cache_files_opened = &cache_files_opened;
    api.cache_header = &cache_header;
    api.cache_read = &cache_read;
    api.cache_release = &cache_release;
    return api;
}

}  // namespace
}  // namespace gdof::io::oiio_module

extern "C" __attribute__((visibility("default"))) const gdof::io::detail::OiioModuleApi* gdof_oiio_module_api() {
    static const gdof::io::detail::OiioModuleApi api = gdof::io::oiio_module::make_api();
    return &api;
}

// EXR reading through io::read_image: flat, deep, multipart, tiled, the
// attributes and id manifests. The bytes become a .exr file; the read must
// succeed or fail with a message, never crash, hang or leak. The image is
// touched pixel by pixel so a wrong size in the result shows under ASan.
#include "fuzz_support.h"
#include "gdof/io/image_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string path = gdof::fuzz::write_file("in.exr", gdof::fuzz::text(data, size));
    auto r = gdof::io::read_image(path);
    if (!r) return 0;
    volatile double sum = 0;
    const gdof::ImageSet& set = r.value();
    for (std::size_t i = 0; i < set.size(); ++i) {
        if (set.is_deep(i)) {
            const gdof::DeepImage& d = set.deep(i);
            for (int c = 0; c < d.nchannels(); ++c)
                for (std::size_t s = 0; s < d.total_samples(); ++s)
                    sum = sum + (d.channel(c).type == gdof::PixelType::UInt ? double(d.usamples(c)[s])
                                                                            : double(d.samples(c)[s]));
        } else {
            const gdof::Image& img = set.flat(i);
            for (int c = 0; c < img.nchannels(); ++c)
                for (int y = img.data_window().y0; y < img.data_window().y1; ++y)
                    for (int x = img.data_window().x0; x < img.data_window().x1; ++x) sum = sum + img.sample(c, x, y);
        }
    }
    return 0;
}

#include "gaussian_layers.h"

#include <cmath>

#include <opencv2/imgproc.hpp>

#include "gdof/blur_map.h"
#include "gdof/layers.h"

namespace gdof::bench {

Result<Image> gaussian_layers(const Image& rgba_z, const BlurField& field, const Camera& camera, int slices) {
    SliceOptions so;
    so.split.mode = LayerSplit::Mode::Count;
    so.split.count = slices;
    so.extend_px = 0;  // naive: nothing behind the foreground
    auto layers = layers_from_depth_map(rgba_z, so);
    if (!layers) return layers.status();
    std::vector<Image> blurred;
    for (const Layer& l : layers.value()) {
        const Image& img = l.image;
        if (img.data_window().empty()) continue;
        std::vector<float> radius(img.npixels());
        if (Status st = evaluate_blur_map(field, camera, img, PositionSource{}, ImageView::planar(radius.data(), 1, img.data_window())); !st) return st;
        const int a = img.channel_index("A");
        double wsum = 0, rsum = 0;
        for (std::size_t i = 0; i < img.npixels(); ++i)
            if (img.plane(a)[i] > 0 && std::isfinite(radius[i])) wsum += img.plane(a)[i], rsum += img.plane(a)[i] * radius[i];
        const double sigma = wsum > 0 ? 0.5 * rsum / wsum : 0.0;
        // Blur over the whole frame so the spread is not cut at the slice's box.
        const Roi frame = rgba_z.data_window();
        Image out = Image::with_channels({"R", "G", "B", "A"}, frame);
        for (int c = 0; c < 4; ++c) {
            const int src = img.channel_index(std::string(1, "RGBA"[c]));
            cv::Mat m(frame.height(), frame.width(), CV_32F, out.plane(c));
            const Roi dw = img.data_window();
            for (int y = dw.y0; y < dw.y1; ++y)
                for (int x = dw.x0; x < dw.x1; ++x) out.at(c, x, y) = img.at(src, x, y);
            if (sigma > 0.05) cv::GaussianBlur(m, m, cv::Size(0, 0), sigma, sigma, cv::BORDER_REPLICATE);
        }
        blurred.push_back(std::move(out));
    }
    std::vector<const Image*> ptrs;
    for (const Image& b : blurred) ptrs.push_back(&b);
    return composite_layers(ptrs, rgba_z.data_window());
}

}  // namespace gdof::bench

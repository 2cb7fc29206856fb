#include "bench_metrics.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace gdof::bench {

namespace {

double srgb(double v) {
    v = std::clamp(v, 0.0, 1.0);
    return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055;
}

struct Rgb {
    const float *r, *g, *b;
};
Rgb rgb(const Image& img) {
    return {img.plane(img.channel_index("R")), img.plane(img.channel_index("G")), img.plane(img.channel_index("B"))};
}

cv::Mat luminance_srgb(const Image& img) {
    const Rgb c = rgb(img);
    cv::Mat m(img.height(), img.width(), CV_64F);
    for (std::size_t i = 0; i < img.npixels(); ++i)
        m.at<double>(int(i / std::size_t(img.width())), int(i % std::size_t(img.width()))) =
            srgb(0.2126 * c.r[i] + 0.7152 * c.g[i] + 0.0722 * c.b[i]);
    return m;
}

double mean_ssim(const cv::Mat& a, const cv::Mat& b) {
    const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
    auto blur = [](const cv::Mat& m) {
        cv::Mat o;
        cv::GaussianBlur(m, o, cv::Size(11, 11), 1.5, 1.5, cv::BORDER_REFLECT);
        return o;
    };
    const cv::Mat ma = blur(a), mb = blur(b);
    const cv::Mat saa = blur(a.mul(a)) - ma.mul(ma), sbb = blur(b.mul(b)) - mb.mul(mb), sab = blur(a.mul(b)) - ma.mul(mb);
    cv::Mat num = (2 * ma.mul(mb) + c1).mul(2 * sab + c2);
    cv::Mat den = (ma.mul(ma) + mb.mul(mb) + c1).mul(saa + sbb + c2);
    cv::Mat s;
    cv::divide(num, den, s);
    return cv::mean(s)[0];
}

}  // namespace

std::vector<char> discontinuity_mask(const float* z, int w, int h, int radius) {
    std::vector<char> edge(std::size_t(w) * h, 0);
    auto differs = [](float a, float b) {
        if (std::isfinite(a) != std::isfinite(b)) return true;
        if (!std::isfinite(a)) return false;
        return std::fabs(a - b) > 0.1 * std::min(std::fabs(a), std::fabs(b));
    };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float v = z[std::size_t(y) * w + x];
            if ((x + 1 < w && differs(v, z[std::size_t(y) * w + x + 1])) || (y + 1 < h && differs(v, z[std::size_t(y + 1) * w + x])))
                edge[std::size_t(y) * w + x] = 1;
        }
    cv::Mat m(h, w, CV_8U, edge.data());
    cv::Mat k = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius + 1, 2 * radius + 1));
    cv::Mat d;
    cv::dilate(m, d, k);
    std::vector<char> out(std::size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) out[std::size_t(y) * w + x] = d.at<unsigned char>(y, x) ? 1 : 0;
    return out;
}

ErrorMetrics compare(const Image& result, const Image& truth, const std::vector<char>& edge) {
    const Rgb a = rgb(result), b = rgb(truth);
    double l1 = 0, l1b = 0, l2 = 0, l2b = 0, el1 = 0, el1b = 0, al1 = 0, al1b = 0;
    const std::size_t n = truth.npixels();
    for (std::size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            const double va = c == 0 ? a.r[i] : c == 1 ? a.g[i] : a.b[i];
            const double vb = c == 0 ? b.r[i] : c == 1 ? b.g[i] : b.b[i];
            const double d = va - vb;
            l1 += std::fabs(d), l1b += std::fabs(vb), l2 += d * d, l2b += vb * vb;
            if (edge[i]) el1 += std::fabs(d), el1b += std::fabs(vb);
            else al1 += std::fabs(d), al1b += std::fabs(vb);
        }
    ErrorMetrics m;
    m.rel_l1 = l1 / std::max(l1b, 1e-30);
    m.rel_l2 = std::sqrt(l2 / std::max(l2b, 1e-30));
    const double mse = l2 / double(3 * n);
    m.psnr = mse > 0 ? 10 * std::log10(1.0 / mse) : 99.0;
    m.edge_rel_l1 = el1 / std::max(el1b, 1e-30);
    m.away_rel_l1 = al1 / std::max(al1b, 1e-30);
    m.ssim = mean_ssim(luminance_srgb(result), luminance_srgb(truth));
    return m;
}

cv::Mat error_map(const Image& result, const Image& truth, double scale) {
    const Rgb a = rgb(result), b = rgb(truth);
    cv::Mat m(truth.height(), truth.width(), CV_8U);
    for (std::size_t i = 0; i < truth.npixels(); ++i) {
        const double d = 0.2126 * std::fabs(a.r[i] - b.r[i]) + 0.7152 * std::fabs(a.g[i] - b.g[i]) +
                         0.0722 * std::fabs(a.b[i] - b.b[i]);
        m.at<unsigned char>(int(i / std::size_t(truth.width())), int(i % std::size_t(truth.width()))) =
            (unsigned char)std::lround(255 * std::clamp(d / scale, 0.0, 1.0));
    }
    cv::Mat colour;
    cv::applyColorMap(m, colour, cv::COLORMAP_INFERNO);
    return colour;
}

cv::Mat preview(const Image& img) {
    const Rgb c = rgb(img);
    cv::Mat m(img.height(), img.width(), CV_8UC3);
    for (std::size_t i = 0; i < img.npixels(); ++i) {
        auto& p = m.at<cv::Vec3b>(int(i / std::size_t(img.width())), int(i % std::size_t(img.width())));
        p[0] = (unsigned char)std::lround(255 * srgb(c.b[i]));
        p[1] = (unsigned char)std::lround(255 * srgb(c.g[i]));
        p[2] = (unsigned char)std::lround(255 * srgb(c.r[i]));
    }
    return m;
}

Image rgba_over(const Image& img, const Roi& window) {
    Image out = Image::with_channels({"R", "G", "B", "A"}, window);
    const Roi dw = img.data_window();
    for (int c = 0; c < 4; ++c) {
        const int s = img.channel_index(std::string(1, "RGBA"[c]));
        if (s < 0) continue;
        for (int y = std::max(window.y0, dw.y0); y < std::min(window.y1, dw.y1); ++y)
            for (int x = std::max(window.x0, dw.x0); x < std::min(window.x1, dw.x1); ++x) out.at(c, x, y) = img.at(s, x, y);
    }
    return out;
}

}  // namespace gdof::bench

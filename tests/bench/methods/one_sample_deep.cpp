#include "methods/one_sample_deep.h"

#include <algorithm>
#include <array>
#include <numeric>
#include <vector>

#include "bench_cli.h"

namespace gdof::bench {

DeepImage one_sample_deep(const DeepImage& deep) {
    const int z = deep.z_channel();
    const std::array<int, 4> rgba = {deep.channel_index("R"), deep.channel_index("G"), deep.channel_index("B"),
                                     deep.channel_index("A")};
    if (z < 0 || rgba[3] < 0) die("one-sample deep: the deep render has no Z or A channel");
    DeepImage out(deep.channels(), deep.data_window(), deep.display_window());
    out.metadata = deep.metadata;
    const std::size_t n = deep.npixels();
    std::vector<std::uint32_t> counts(n);
    for (std::size_t p = 0; p < n; ++p) counts[p] = deep.sample_count(p) > 0 ? 1 : 0;
    if (Status st = out.set_sample_counts(counts); !st) die(st.message());
    std::vector<std::size_t> order;
    for (std::size_t p = 0; p < n; ++p) {
        const std::uint32_t k = deep.sample_count(p);
        if (!k) continue;
        const std::size_t s0 = deep.first_sample(p), o = out.first_sample(p);
        order.resize(k);
        std::iota(order.begin(), order.end(), s0);
        const float* zs = deep.samples(z);
        std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return zs[a] < zs[b]; });
        for (int c = 0; c < deep.nchannels(); ++c) {
            if (deep.channel(c).type == PixelType::UInt) out.usamples(c)[o] = deep.usamples(c)[order[0]];
            else out.samples(c)[o] = deep.samples(c)[order[0]];
        }
        // Premultiplied colour and alpha, `over` from the front.
        std::array<double, 4> acc = {0, 0, 0, 0};
        double through = 1.0;
        for (std::size_t s : order) {
            for (int c = 0; c < 4; ++c)
                if (rgba[std::size_t(c)] >= 0) acc[std::size_t(c)] += through * deep.samples(rgba[std::size_t(c)])[s];
            through *= 1.0 - double(deep.samples(rgba[3])[s]);
        }
        for (int c = 0; c < 4; ++c)
            if (rgba[std::size_t(c)] >= 0) out.samples(rgba[std::size_t(c)])[o] = float(acc[std::size_t(c)]);
    }
    return out;
}

}  // namespace gdof::bench

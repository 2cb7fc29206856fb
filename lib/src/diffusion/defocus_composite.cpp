// Back-to-front `over` of a layer (diffused or passed through) onto the
// defocus result.
#include "diffusion/defocus_internal.h"

namespace gdof::defocus_detail {

Status composite_over(Image& dst, const std::array<const float*, 4>& src, const Roi& src_window, const Exec& exec) {
    const Roi r = intersect(dst.data_window(), src_window);
    if (r.empty()) return Status::ok();
    std::array<float*, 4> d{dst.plane(0), dst.plane(1), dst.plane(2), dst.plane(3)};
    const std::size_t sw = std::size_t(src_window.width());
    const bool done = parallel_for(exec, r.height(), [&](long y0, long y1) {
        for (long yl = y0; yl < y1; ++yl) {
            const int y = r.y0 + int(yl);
            const std::size_t so = std::size_t(y - src_window.y0) * sw + std::size_t(r.x0 - src_window.x0);
            const std::size_t doff = dst.offset(r.x0, y);
            for (int i = 0; i < r.width(); ++i) {
                const std::size_t s = so + std::size_t(i), o = doff + std::size_t(i);
                const bool untouched = d[0][o] == 0.0f && d[1][o] == 0.0f && d[2][o] == 0.0f && d[3][o] == 0.0f;
                if (untouched) {
                    for (int c = 0; c < 4; ++c) d[std::size_t(c)][o] = src[std::size_t(c)][s];
                    continue;
                }
                const float k = 1.0f - src[3][s];
                for (int c = 0; c < 4; ++c) d[std::size_t(c)][o] = src[std::size_t(c)][s] + k * d[std::size_t(c)][o];
            }
        }
    }, 8);
    if (!done) return Status::cancelled("defocus");
    return Status::ok();
}

}  // namespace gdof::defocus_detail

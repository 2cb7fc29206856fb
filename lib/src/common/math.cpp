#include "gdof/math.h"

#include <cmath>
#include <utility>

namespace gdof {

std::optional<Mat44> inverse(const Mat44& a) {
    double t[4][8];
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            t[i][j] = a.m[i][j];
            t[i][j + 4] = (i == j) ? 1.0 : 0.0;
        }
    for (int col = 0; col < 4; ++col) {
        int piv = col;
        for (int r = col + 1; r < 4; ++r)
            if (std::fabs(t[r][col]) > std::fabs(t[piv][col])) piv = r;
        if (!(std::fabs(t[piv][col]) > 1e-300)) return std::nullopt;
        if (piv != col)
            for (int j = 0; j < 8; ++j) std::swap(t[piv][j], t[col][j]);
        double inv = 1.0 / t[col][col];
        for (int j = 0; j < 8; ++j) t[col][j] *= inv;
        for (int r = 0; r < 4; ++r) {
            if (r == col) continue;
            double f = t[r][col];
            if (f != 0.0)
                for (int j = 0; j < 8; ++j) t[r][j] -= f * t[col][j];
        }
    }
    Mat44 out;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) out.m[i][j] = t[i][j + 4];
    return out;
}

}  // namespace gdof

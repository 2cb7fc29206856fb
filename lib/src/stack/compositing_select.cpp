// Method 2, steps 1 and 2 (compositing.h): the stack index and the per-pixel
// choice of references, with the soft-mode weights.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "gdof/compositing.h"

namespace gdof {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// One term of the deviation: (is it infinite, finite value).
inline void add_term(double a, double b, Deviation& d) {
    if (a == b) return;  // also both +inf
    if (std::isinf(a) || std::isinf(b)) ++d.infinite_terms;
    else d.value += std::abs(a - b);
}

struct Cand {
    Deviation dev;
    int index;
    bool operator<(const Cand& o) const {
        if (dev < o.dev) return true;
        if (o.dev < dev) return false;
        return index < o.index;
    }
};

// Keeps the k best candidates, sorted.
struct BestK {
    Cand* c;
    int k, n = 0;
    void offer(const Cand& x) {
        if (n == k && !(x < c[n - 1])) return;
        int i = n < k ? n++ : k - 1;
        while (i > 0 && x < c[i - 1]) {
            c[i] = c[i - 1];
            --i;
        }
        c[i] = x;
    }
    // Lower bound that can no longer enter.
    bool full_and_beaten(const Deviation& lb) const { return n == k && c[n - 1].dev < lb; }
};

}  // namespace

Deviation stack_deviation(double nd, double fd, double nr, double fr) {
    Deviation d;
    if (std::isnan(nd) || std::isnan(fd)) {
        d.infinite_terms = 2;
        return d;
    }
    add_term(nd, nr, d);
    add_term(fd, fr, d);
    return d;
}

Result<StackIndex> StackIndex::build(const std::vector<DepthInterval>& refs) {
    StackIndex s;
    s.refs_ = refs;
    s.n_ = int(refs.size());
    for (int i = 0; i < s.n_; ++i) {
        const DepthInterval& r = refs[std::size_t(i)];
        if (!std::isfinite(r.near) || r.near < 0)
            return Status::error("reference " + std::to_string(i) + ": near must be finite and >= 0");
        if (std::isnan(r.far) || r.far < r.near)
            return Status::error("reference " + std::to_string(i) + ": far must be >= near");
        (std::isinf(r.far) ? s.infinite_far_ : s.finite_far_).push_back({r.near, r.far, i});
    }
    auto by_near = [](const Entry& a, const Entry& b) { return a.near != b.near ? a.near < b.near : a.index < b.index; };
    std::sort(s.finite_far_.begin(), s.finite_far_.end(), by_near);
    std::sort(s.infinite_far_.begin(), s.infinite_far_.end(), by_near);
    return s;
}

int StackIndex::nearest(double nd, double fd, int k, int* index, Deviation* deviation) const {
    if (k <= 0 || n_ == 0 || std::isnan(nd) || std::isnan(fd)) return 0;
    Cand stack_buf[16];
    std::vector<Cand> heap_buf;
    Cand* buf = stack_buf;
    if (k > 16) {
        heap_buf.resize(std::size_t(k));
        buf = heap_buf.data();
    }
    BestK best{buf, k};

    if (!std::isfinite(nd)) {
        // Unusual (a desired near of +inf): every reference, plainly.
        for (int i = 0; i < n_; ++i)
            best.offer({stack_deviation(nd, fd, refs_[std::size_t(i)].near, refs_[std::size_t(i)].far), i});
    } else {
        // Within a group the far term has one status: 0 infinite terms in the
        // group matching the desired far's finiteness, 1 in the other. So the
        // lower bound of an entry is (group's infinite terms, |nd - near|).
        auto walk = [&](const std::vector<Entry>& g) {
            if (g.empty()) return;
            auto it = std::lower_bound(g.begin(), g.end(), nd, [](const Entry& e, double v) { return e.near < v; });
            long r = long(it - g.begin()), l = r - 1;
            const long n = long(g.size());
            while (l >= 0 || r < n) {
                const double dl = l >= 0 ? nd - g[std::size_t(l)].near : kInf;
                const double dr = r < n ? g[std::size_t(r)].near - nd : kInf;
                const bool take_left = dl <= dr;
                const Entry& e = g[std::size_t(take_left ? l : r)];
                Deviation lb;
                if (std::isinf(e.far) != std::isinf(fd)) lb.infinite_terms = 1;
                lb.value = take_left ? dl : dr;
                if (best.full_and_beaten(lb)) break;  // entries further out are no better
                best.offer({stack_deviation(nd, fd, e.near, e.far), e.index});
                if (take_left) --l;
                else ++r;
            }
        };
        const bool far_inf = std::isinf(fd);
        walk(far_inf ? infinite_far_ : finite_far_);
        walk(far_inf ? finite_far_ : infinite_far_);
    }
    for (int i = 0; i < best.n; ++i) {
        index[i] = buf[i].index;
        if (deviation) deviation[i] = buf[i].dev;
    }
    return best.n;
}

int StackSelection::references_used() const {
    return int(std::count(used.begin(), used.end(), char(1)));
}

std::vector<int> StackSelection::used_references() const {
    std::vector<int> r;
    for (std::size_t i = 0; i < used.size(); ++i)
        if (used[i]) r.push_back(int(i));
    return r;
}

Result<StackSelection> select_references(const StackIndex& index, const DesiredFocus& desired,
                                         const CompositeOptions& settings, const Exec& exec) {
    if (index.size() == 0) return Status::error("the stack has no references");
    if (settings.soft_k < 1 || settings.soft_k > 16)
        return Status::error("soft: K must be 1 to 16, got " + std::to_string(settings.soft_k));
    if (desired.near.size() != desired.npixels() || desired.far.size() != desired.npixels())
        return Status::error("desired focus: near/far planes do not match the window");
    const int k = std::min(settings.soft_k, index.size());
    const bool soft = k > 1;
    const int q = soft ? k + 1 : 1;  // soft mode also needs the first excluded one (R)

    StackSelection s;
    s.window = desired.window;
    s.k = k;
    const std::size_t np = desired.npixels();
    s.index.assign(np * std::size_t(k), -1);
    if (soft) s.weight.assign(np * std::size_t(k), 0.0f);
    s.deviation.assign(np, std::numeric_limits<float>::quiet_NaN());

    const int W = desired.window.width(), H = desired.window.height();
    // Per row chunk, which references were chosen (merged afterwards: no sharing).
    const long chunk = 16;
    const long nchunks = (H + chunk - 1) / chunk;
    std::vector<std::vector<char>> used(std::size_t(std::max(nchunks, 1L)));
    const bool ok = parallel_for(exec, nchunks, [&](long c0, long c1) {
        std::vector<int> idx(static_cast<std::size_t>(q));
        std::vector<Deviation> dev(static_cast<std::size_t>(q));
        for (long c = c0; c < c1; ++c) {
            std::vector<char>& u = used[std::size_t(c)];
            u.assign(std::size_t(index.size()), 0);
            for (long y = c * chunk; y < std::min<long>(H, (c + 1) * chunk); ++y)
                for (int x = 0; x < W; ++x) {
                    const std::size_t o = std::size_t(y) * std::size_t(W) + std::size_t(x);
                    const int n = index.nearest(desired.near[o], desired.far[o], q, idx.data(), dev.data());
                    if (n == 0) continue;
                    s.deviation[o] = float(dev[0].as_double());
                    std::int32_t* out = &s.index[o * std::size_t(k)];
                    if (!soft) {
                        out[0] = idx[0];
                        u[std::size_t(idx[0])] = 1;
                        continue;
                    }
                    float* w = &s.weight[o * std::size_t(k)];
                    // Candidates with as many infinite terms as the best.
                    int m = 0;
                    while (m < std::min(n, k) && dev[std::size_t(m)].infinite_terms == dev[0].infinite_terms) ++m;
                    double R = kInf;
                    if (n > m && dev[std::size_t(m)].infinite_terms == dev[0].infinite_terms) R = dev[std::size_t(m)].value;
                    double wt[64];
                    double sum = 0;
                    const int mm = std::min(m, 64);
                    if (dev[0].value == 0.0) {
                        wt[0] = 1.0, sum = 1.0;
                        for (int i = 1; i < mm; ++i) wt[i] = 0.0;
                    } else {
                        for (int i = 0; i < mm; ++i) {
                            const double d = dev[std::size_t(i)].value;
                            const double a = std::isinf(R) ? 1.0 / d : (R - d) / (R * d);
                            wt[i] = a > 0 ? a * a : 0.0;
                            sum += wt[i];
                        }
                        if (!(sum > 0) || !std::isfinite(sum)) {
                            wt[0] = 1.0, sum = 1.0;
                            for (int i = 1; i < mm; ++i) wt[i] = 0.0;
                        }
                    }
                    int slot = 0;
                    for (int i = 0; i < mm; ++i) {
                        if (wt[i] <= 0.0) continue;
                        out[slot] = idx[std::size_t(i)];
                        w[slot] = float(wt[i] / sum);
                        u[std::size_t(idx[std::size_t(i)])] = 1;
                        ++slot;
                    }
                }
        }
    });
    if (!ok) return Status::cancelled();
    s.used.assign(std::size_t(index.size()), 0);
    for (const auto& u : used)
        for (std::size_t i = 0; i < u.size(); ++i)
            if (u[i]) s.used[i] = 1;
    return s;
}

}  // namespace gdof

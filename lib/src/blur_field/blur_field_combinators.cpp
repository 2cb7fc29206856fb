// Blur-field combinators: min, max, add, mul, scale, clamp (and the zero field).
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "blur_field/blur_field_nodes.h"

namespace gdof::bf {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

class NaryNode final : public Node {
public:
    NaryNode(Op op, std::vector<NodePtr> c) : op_(op), children_(std::move(c)) {
        for (const auto& ch : children_) needs_ |= ch->needs();
    }
    void eval(const Batch& b, double* out) const override {
        children_[0]->eval(b, out);
        double tmp[kChunk];
        for (std::size_t c = 1; c < children_.size(); ++c) {
            children_[c]->eval(b, tmp);
            switch (op_) {
                case Op::Min:
                    for (std::size_t i = 0; i < b.n; ++i)
                        out[i] = (std::isnan(out[i]) || std::isnan(tmp[i])) ? kNaN : std::min(out[i], tmp[i]);
                    break;
                case Op::Max:
                    for (std::size_t i = 0; i < b.n; ++i)
                        out[i] = (std::isnan(out[i]) || std::isnan(tmp[i])) ? kNaN : std::max(out[i], tmp[i]);
                    break;
                case Op::Add:
                    for (std::size_t i = 0; i < b.n; ++i) out[i] += tmp[i];
                    break;
                case Op::Mul:
                    // 0 * inf = 0: a sharp factor keeps the point sharp.
                    for (std::size_t i = 0; i < b.n; ++i)
                        out[i] = (out[i] == 0 || tmp[i] == 0) ? (std::isnan(out[i] + tmp[i]) ? kNaN : 0.0)
                                                              : out[i] * tmp[i];
                    break;
            }
        }
    }
    unsigned needs() const override { return needs_; }
    void breakpoints(const Ray& r, double a, double b, std::vector<double>& out) const override {
        std::vector<double> own;
        for (const auto& ch : children_) ch->breakpoints(r, a, b, own);
        if ((op_ == Op::Min || op_ == Op::Max) && children_.size() > 1) {
            // Kinks where two children cross.
            const std::vector<double> grid = make_grid(a, b, own);
            for (std::size_t i = 0; i < children_.size(); ++i)
                for (std::size_t j = i + 1; j < children_.size(); ++j) {
                    const Node& ci = *children_[i];
                    const Node& cj = *children_[j];
                    auto diff = [&](double d) {
                        const double u = eval_on_ray(ci, r, d), v = eval_on_ray(cj, r, d);
                        if (std::isinf(u) && std::isinf(v)) return 0.0;
                        return u - v;
                    };
                    level_crossings(diff, 0.0, grid, 16, own);
                }
        }
        out.insert(out.end(), own.begin(), own.end());
    }
    bool linear_between_breakpoints() const override {
        if (op_ == Op::Mul) {
            // A product is linear only if at most one factor is not constant;
            // we only know "linear", so require a single child.
            return children_.size() == 1 && children_[0]->linear_between_breakpoints();
        }
        for (const auto& ch : children_)
            if (!ch->linear_between_breakpoints()) return false;
        return true;
    }
    std::string describe() const override {
        static const char* names[] = {"min", "max", "add", "mul"};
        std::string s = std::string(names[int(op_)]) + "(";
        for (std::size_t i = 0; i < children_.size(); ++i) s += (i ? ", " : "") + children_[i]->describe();
        return s + ")";
    }

    Result<NodePtr> refocused(double d) const override {
        std::vector<NodePtr> kids = children_;
        bool changed = false;
        for (NodePtr& k : kids) {
            auto r = k->refocused(d);
            if (!r) return r;
            if (*r) k = *r, changed = true;
        }
        return changed ? NodePtr(std::make_shared<NaryNode>(op_, std::move(kids))) : NodePtr();
    }

private:
    Op op_;
    std::vector<NodePtr> children_;
    unsigned needs_ = 0;
};

class ScaleNode final : public Node {
public:
    ScaleNode(NodePtr c, double f) : child_(std::move(c)), factor_(f) {}
    void eval(const Batch& b, double* out) const override {
        child_->eval(b, out);
        for (std::size_t i = 0; i < b.n; ++i)
            out[i] = std::isnan(out[i]) ? kNaN : (out[i] == 0 || factor_ == 0) ? 0.0 : out[i] * factor_;
    }
    unsigned needs() const override { return child_->needs(); }
    void breakpoints(const Ray& r, double a, double b, std::vector<double>& out) const override {
        child_->breakpoints(r, a, b, out);
    }
    bool linear_between_breakpoints() const override { return child_->linear_between_breakpoints(); }
    std::string describe() const override { return "scale(" + child_->describe() + ")"; }
    Result<NodePtr> refocused(double d) const override {
        auto r = child_->refocused(d);
        if (!r || !*r) return r;
        return NodePtr(std::make_shared<ScaleNode>(*r, factor_));
    }

private:
    NodePtr child_;
    double factor_;
};

class ClampNode final : public Node {
public:
    ClampNode(NodePtr c, double lo, double hi) : child_(std::move(c)), lo_(lo), hi_(hi) {}
    void eval(const Batch& b, double* out) const override {
        child_->eval(b, out);
        for (std::size_t i = 0; i < b.n; ++i) out[i] = std::isnan(out[i]) ? kNaN : std::clamp(out[i], lo_, hi_);
    }
    unsigned needs() const override { return child_->needs(); }
    void breakpoints(const Ray& r, double a, double b, std::vector<double>& out) const override {
        std::vector<double> own;
        child_->breakpoints(r, a, b, own);
        const std::vector<double> grid = make_grid(a, b, own);
        auto f = [&](double d) { return eval_on_ray(*child_, r, d); };
        if (lo_ > 0) level_crossings(f, lo_, grid, 16, own);
        if (std::isfinite(hi_)) level_crossings(f, hi_, grid, 16, own);
        out.insert(out.end(), own.begin(), own.end());
    }
    bool linear_between_breakpoints() const override { return child_->linear_between_breakpoints(); }
    std::string describe() const override { return "clamp(" + child_->describe() + ")"; }
    Result<NodePtr> refocused(double d) const override {
        auto r = child_->refocused(d);
        if (!r || !*r) return r;
        return NodePtr(std::make_shared<ClampNode>(*r, lo_, hi_));
    }

private:
    NodePtr child_;
    double lo_, hi_;
};

class ZeroNode final : public Node {
public:
    void eval(const Batch& b, double* out) const override { std::fill(out, out + b.n, 0.0); }
    unsigned needs() const override { return 0; }
    void breakpoints(const Ray&, double, double, std::vector<double>&) const override {}
    bool linear_between_breakpoints() const override { return true; }
    std::string describe() const override { return "zero"; }
};

}  // namespace

NodePtr make_nary(Op op, std::vector<NodePtr> children) {
    if (children.size() == 1 && op != Op::Mul) return children[0];
    return std::make_shared<NaryNode>(op, std::move(children));
}
NodePtr make_scale(NodePtr child, double factor) { return std::make_shared<ScaleNode>(std::move(child), factor); }
NodePtr make_clamp(NodePtr child, double lo, double hi) {
    return std::make_shared<ClampNode>(std::move(child), lo, hi);
}
NodePtr make_zero() { return std::make_shared<ZeroNode>(); }

}  // namespace gdof::bf

// PsfField::parse: the JSON of docs/psf_field.md through json_read (unknown
// keys and bad values name the key path). A blend's weight is a blur-field
// node, parsed by BlurField::parse and its messages put under the key path.
#include <algorithm>
#include <cmath>

#include "blur_field/context_image.h"
#include "common/json_read.h"
#include "psf_field/psf_field_nodes.h"

namespace gdof {

namespace {

using json_read::Object;
using json_read::Value;

class Parser {
public:
    explicit Parser(const BlurField::Context& ctx) : ctx_(ctx) {}

    psf::NodePtr node(const Value& v) {
        const Object kind_only = v.object();
        const std::string kind =
            kind_only.get("kind").choice({"defocus", "swirl", "depth", "image_map", "sum", "blend"});
        if (kind == "defocus") {
            const Object o = v.object({"kind", "scale", "comment"});
            return psf::make_defocus(number_or(o, "scale", 1.0));
        }
        if (kind == "swirl") {
            const Object o = v.object({"kind", "strength", "power", "comment"});
            const double power = number_or(o, "power", 1.0);
            if (power < 0.0) json_read::fail(o.path("power"), "must be >= 0, got " + json_read::format_number(power));
            return psf::make_swirl(number_or(o, "strength", 1.0), power);
        }
        if (kind == "depth") {
            const Object o = v.object({"kind", "offset", "distance", "comment"});
            return psf::make_depth(number_or(o, "offset", 0.0), number_or(o, "distance", 0.0));
        }
        if (kind == "image_map") return image_map(v.object({"kind", "image", "channels", "scale", "comment"}, {"image"}));
        if (kind == "sum") {
            const Object o = v.object({"kind", "children", "comment"}, {"children"});
            std::vector<psf::NodePtr> c;
            for (const Value& ch : o.get("children").non_empty_array("PSF field objects")) c.push_back(node(ch));
            return psf::make_sum(std::move(c));
        }
        const Object o = v.object({"kind", "children", "weight", "comment"}, {"children", "weight"});
        const int index = weights_++;  // before the children: tree (pre-)order, as collect_weights
        BlurField w = weight(o.get("weight"));
        const auto ch = o.get("children").array();
        if (ch.size() != 2)
            json_read::fail(o.path("children"), "must hold exactly 2 PSF fields, got " + std::to_string(ch.size()));
        psf::NodePtr a = node(ch[0]);
        psf::NodePtr b = node(ch[1]);
        return psf::make_blend(std::move(a), std::move(b), std::move(w), index);
    }

    int weights() const { return weights_; }

private:
    static double number_or(const Object& o, const std::string& key, double fallback) {
        const auto v = o.find(key);
        return v ? v->number() : fallback;
    }

    // The map read as the blur field's image_map reads its image (a name
    // supplied by the program, else a file relative to the JSON); its
    // channels, all of them or those named, must be 1, 2 or 4.
    psf::NodePtr image_map(const Object& o) {
        const std::string ref = o.get("image").string();
        std::shared_ptr<const Image> img = blur_field_detail::context_image(ctx_, ref, o.path("image"));
        std::vector<int> ch;
        if (const auto names = o.find("channels")) {
            for (const Value& n : names->array()) {
                const int c = img->channel_index(n.string());
                if (c < 0) n.fail("image \"" + ref + "\" has no channel \"" + n.string() + "\"", StatusCode::NotFound);
                ch.push_back(c);
            }
        } else {
            for (int c = 0; c < img->nchannels(); ++c) ch.push_back(c);
        }
        if (ch.size() != 1 && ch.size() != 2 && ch.size() != 4)
            json_read::fail(o.path(o.find("channels") ? "channels" : "image"),
                            "image \"" + ref + "\": " + std::to_string(ch.size()) +
                                " channels; expected 1 (a scale), 2 (x and y scales) or 4 (a 2x2 matrix)");
        return psf::make_image_map(std::move(img), std::move(ch), number_or(o, "scale", 1.0), ref);
    }

    BlurField weight(const Value& v) {
        if (!v.raw().is_object()) v.fail("must be a blur field object {\"kind\": ...}, got " + json_read::type_name(v.raw()));
        json_read::json doc = json_read::json::object();
        doc["blurfield"] = v.raw();
        auto f = BlurField::parse(doc.dump(), ctx_);
        if (!f) json_read::fail(v.path(), "not a valid blur field: " + f.message(), f.status().code());
        return std::move(f).value();
    }

    const BlurField::Context& ctx_;
    int weights_ = 0;
};

}  // namespace

PsfField::PsfField() : root_(psf::make_defocus(1.0)) {}

Result<PsfField> PsfField::parse(std::string_view text, const BlurField::Context& ctx) {
    return json_read::read_document(text, "", [&](const Value& root) {
        if (!root.raw().is_object())
            root.fail("must be an object {\"psf_field\": {...}}, got " + json_read::type_name(root.raw()));
        const Object top = root.object({"psf_field", "samples", "comment"}, {"psf_field"});
        PsfField f;
        Parser p(ctx);
        f.root_ = p.node(top.get("psf_field"));
        f.weights_ = p.weights();
        if (const auto s = top.find("samples")) {
            const long long n = s->integer();
            if (n < 0 || n > 65536) json_read::fail("samples", "must be 0 (automatic) to 65536, got " + std::to_string(n));
            f.samples_ = int(n);
        }
        return f;
    });
}

bool PsfField::moves_depth() const { return root_->moves_depth(); }
std::string PsfField::describe() const { return root_->describe(); }
int PsfField::weight_count() const { return weights_; }

void PsfField::evaluate_weights(const Camera& camera, double px, double py, double depth, float* out) const {
    std::vector<const BlurField*> w;
    root_->collect_weights(w);
    for (std::size_t i = 0; i < w.size(); ++i) {
        const float v = w[i]->evaluate_pixel(camera, px, py, depth);
        out[i] = std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f;
    }
}

PsfDisplacement PsfField::displace(const PsfPoint& point, double u, double v, const Roi& frame) const {
    return root_->displace(point, u, v, frame);
}

}  // namespace gdof

// Sources over layers already made (layers.h, LayerSource): a list held or
// borrowed, served as it is.
#include "layers/layers_internal.h"

namespace gdof {

namespace {

class ListedLayers final : public LayerSource {
public:
    ListedLayers(const std::vector<Layer>* borrowed, std::vector<Layer> owned, Roi frame, Roi display)
        : owned_(std::move(owned)), layers_(borrowed ? borrowed : &owned_), frame_(frame), display_(display) {}
    int size() const override { return int(layers_->size()); }
    Roi frame() const override { return frame_; }
    Roi display_window() const override { return display_; }
    Result<const Layer*> make(int i, Layer&, const Exec&) const override {
        if (i < 0 || i >= size()) return Status::error("layers: no layer " + std::to_string(i));
        return &(*layers_)[std::size_t(i)];
    }

private:
    std::vector<Layer> owned_;
    const std::vector<Layer>* layers_;
    Roi frame_, display_;
};

// Another source, served as it is, with its largest blur radius known.
class KnownRadiusSource final : public LayerSource {
public:
    KnownRadiusSource(std::unique_ptr<LayerSource> inner, double radius) : inner_(std::move(inner)), radius_(radius) {}
    int size() const override { return inner_->size(); }
    Roi frame() const override { return inner_->frame(); }
    Roi display_window() const override { return inner_->display_window(); }
    Result<const Layer*> make(int i, Layer& storage, const Exec& exec) const override {
        return inner_->make(i, storage, exec);
    }
    double largest_blur_radius() const override { return radius_; }

private:
    std::unique_ptr<LayerSource> inner_;
    double radius_;
};

// The union of the layers' data windows and the display windows.
void windows_of(const std::vector<Layer>& layers, Roi& frame, Roi& display) {
    for (const Layer& L : layers) {
        frame = unite(frame, L.image.data_window());
        display = unite(display, L.image.display_window());
    }
}

}  // namespace

namespace layers_detail {

Result<std::vector<Layer>> make_all(const LayerSource& source, const Exec& exec) {
    std::vector<Layer> layers(static_cast<std::size_t>(source.size()));
    for (int i = 0; i < source.size(); ++i) {
        if (exec.is_cancelled()) return Status::cancelled();
        auto made = source.make(i, layers[std::size_t(i)], exec);
        if (!made) return made.status();
        if (*made != &layers[std::size_t(i)]) layers[std::size_t(i)] = **made;
    }
    return layers;
}

Image layer_image(bool with_positions, const Roi& box, const Roi& display, const Metadata& metadata,
                  const std::string& name, const std::string& view) {
    std::vector<ChannelSpec> specs;
    for (const char* c : {"R", "G", "B", "A", "Z", "P.x", "P.y", "P.z"})
        if (with_positions || specs.size() < 5) specs.push_back({c, PixelType::Float});
    Image img = Image::uninitialized(std::move(specs), box, display);
    img.metadata = metadata;
    img.name = name;
    img.view = view;
    return img;
}

}  // namespace layers_detail

std::unique_ptr<LayerSource> source_of(const std::vector<Layer>& front_to_back) {
    Roi frame, display;
    windows_of(front_to_back, frame, display);
    return std::make_unique<ListedLayers>(&front_to_back, std::vector<Layer>{}, frame, display);
}

std::unique_ptr<LayerSource> source_of(std::vector<Layer>&& front_to_back) {
    Roi frame, display;
    windows_of(front_to_back, frame, display);
    return std::make_unique<ListedLayers>(nullptr, std::move(front_to_back), frame, display);
}

std::unique_ptr<LayerSource> with_largest_blur_radius(std::unique_ptr<LayerSource> source, double radius) {
    return std::make_unique<KnownRadiusSource>(std::move(source), radius);
}

}  // namespace gdof

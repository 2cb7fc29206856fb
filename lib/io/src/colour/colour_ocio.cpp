// Colour module: configs loaded by OpenColorIO (--colorconfig FILE or $OCIO).
// The OCIO config is immutable after loading; CPU processors are built once
// per (from, to) pair under a mutex and then applied without locking
// (OCIO's CPUProcessor::apply is const and thread-safe).
#include <OpenColorIO/OpenColorIO.h>

#include <filesystem>
#include <map>
#include <mutex>
#include <system_error>
#include <utility>

#include "colour/colour_internal.h"

namespace OCIO = OCIO_NAMESPACE;

namespace gdof::io {

namespace {

class OcioConfig final : public ColourConfig {
public:
    OcioConfig(OCIO::ConstConfigRcPtr config, std::string path) : config_(std::move(config)), path_(std::move(path)) {}

    std::string description() const override {
        std::string d = "OpenColorIO " + std::string(OCIO::GetVersion()) + " config '" + path_ + "'";
        const char* name = config_->getName();
        if (name && *name) d += " (" + std::string(name) + ")";
        return d;
    }

    std::vector<std::string> colour_spaces() const override {
        std::vector<std::string> out;
        const int n = config_->getNumColorSpaces(OCIO::SEARCH_REFERENCE_SPACE_ALL, OCIO::COLORSPACE_ALL);
        for (int i = 0; i < n; ++i)
            out.emplace_back(config_->getColorSpaceNameByIndex(OCIO::SEARCH_REFERENCE_SPACE_ALL,
                                                               OCIO::COLORSPACE_ALL, i));
        return out;
    }

    std::string resolve(const std::string& name) const override {
        if (name.empty()) return {};
        try {
            // Accepts names, aliases and roles.
            OCIO::ConstColorSpaceRcPtr cs = config_->getColorSpace(name.c_str());
            if (cs) return cs->getName();
        } catch (const OCIO::Exception&) {
        }
        return {};
    }

    bool is_linear(const std::string& name) const override {
        try {
            OCIO::ConstColorSpaceRcPtr cs = config_->getColorSpace(name.c_str());
            if (!cs) return false;
            if (cs->isData()) return true;  // data: no curve to undo
            const std::string enc = detail::ascii_lower(cs->getEncoding());
            if (enc == "scene-linear" || enc == "display-linear") return true;
            if (!enc.empty()) return false;
            // Without an encoding: the scene_linear role, or the reference
            // space itself (no transforms to or from it).
            if (OCIO::ConstColorSpaceRcPtr lin = config_->getColorSpace(OCIO::ROLE_SCENE_LINEAR))
                if (std::string(lin->getName()) == cs->getName()) return true;
            if (cs->getReferenceSpaceType() != OCIO::REFERENCE_SPACE_SCENE) return false;
            if (!cs->getTransform(OCIO::COLORSPACE_DIR_TO_REFERENCE) &&
                !cs->getTransform(OCIO::COLORSPACE_DIR_FROM_REFERENCE))
                return true;
            // Linear if the way to the scene-linear space is matrices only.
            OCIO::ConstColorSpaceRcPtr lin = config_->getColorSpace(OCIO::ROLE_SCENE_LINEAR);
            if (!lin || !is_linear(lin->getName())) return false;
            OCIO::ConstProcessorRcPtr p = config_->getProcessor(cs->getName(), lin->getName());
            OCIO::GroupTransformRcPtr g = p->getOptimizedProcessor(OCIO::OPTIMIZATION_DEFAULT)->createGroupTransform();
            for (int i = 0; i < g->getNumTransforms(); ++i)
                if (g->getTransform(i)->getTransformType() != OCIO::TRANSFORM_TYPE_MATRIX) return false;
            return true;
        } catch (const OCIO::Exception&) {
            return false;
        }
    }

    Status convert(Image& image, const std::string& from, const std::string& to) const override {
        auto proc = processor(from, to);
        if (!proc) return proc.status();
        OCIO::ConstCPUProcessorRcPtr cpu = proc.value();
        if (!cpu) return Status::ok();  // no-op
        return detail::for_each_colour_plane(image, [&](float* r, float* g, float* b, std::size_t n) {
            return apply(*cpu, r, g, b, n);
        });
    }

    Status convert_planes(float* r, float* g, float* b, std::size_t n, const std::string& from,
                          const std::string& to) const override {
        auto proc = processor(from, to);
        if (!proc) return proc.status();
        if (!proc.value() || n == 0) return Status::ok();
        return apply(*proc.value(), r, g, b, n);
    }

private:
    // nullptr (as a value) means the conversion is a no-op.
    Result<OCIO::ConstCPUProcessorRcPtr> processor(const std::string& from, const std::string& to) const {
        const std::string a = resolve(from);
        if (a.empty()) return Status::error("unknown colour space '" + from + "' in " + description());
        const std::string b = resolve(to);
        if (b.empty()) return Status::error("unknown colour space '" + to + "' in " + description());
        if (a == b) return OCIO::ConstCPUProcessorRcPtr();
        std::lock_guard<std::mutex> lock(mu_);
        auto key = std::make_pair(a, b);
        auto it = cache_.find(key);
        if (it != cache_.end()) return it->second;
        try {
            OCIO::ConstProcessorRcPtr p = config_->getProcessor(a.c_str(), b.c_str());
            OCIO::ConstCPUProcessorRcPtr cpu = p->isNoOp() ? OCIO::ConstCPUProcessorRcPtr() : p->getDefaultCPUProcessor();
            cache_.emplace(key, cpu);
            return cpu;
        } catch (const OCIO::Exception& e) {
            return Status::error("converting from '" + from + "' to '" + to + "': " + e.what());
        }
    }

    static Status apply(const OCIO::CPUProcessor& cpu, float* r, float* g, float* b, std::size_t n) {
        try {
            OCIO::PlanarImageDesc desc(r, g, b, nullptr, long(n), 1);
            cpu.apply(desc);
        } catch (const OCIO::Exception& e) {
            return Status::error(std::string("OpenColorIO: ") + e.what());
        }
        return Status::ok();
    }

    OCIO::ConstConfigRcPtr config_;
    std::string path_;
    mutable std::mutex mu_;
    mutable std::map<std::pair<std::string, std::string>, OCIO::ConstCPUProcessorRcPtr> cache_;
};

}  // namespace

namespace detail {

Result<std::shared_ptr<const ColourConfig>> load_ocio_config(const std::string& path) {
    std::error_code ec;
    if (path.empty()) return Status::error("colour config: empty path");
    if (!std::filesystem::exists(path, ec))
        return Status::error("colour config '" + path + "': file not found");
    if (std::filesystem::is_directory(path, ec))
        return Status::error("colour config '" + path + "': is a folder, not a .ocio file");
    try {
        OCIO::ConstConfigRcPtr config = OCIO::Config::CreateFromFile(path.c_str());
        if (!config) return Status::error("colour config '" + path + "': could not be loaded");
        config->validate();
        return std::shared_ptr<const ColourConfig>(std::make_shared<OcioConfig>(config, path));
    } catch (const OCIO::Exception& e) {
        return Status::error("colour config '" + path + "': " + e.what());
    } catch (const std::exception& e) {
        return Status::error("colour config '" + path + "': " + e.what());
    }
}

}  // namespace detail

}  // namespace gdof::io

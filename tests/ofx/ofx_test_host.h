// A small OpenFX host for the plugin tests, written here: it dlopens a
// bundle, calls OfxGetNumberOfPlugins / OfxGetPlugin, and implements the
// property, parameter, image effect, message (v1, v2), multithread and
// memory suites well enough to run the real action sequence (load, describe,
// describeInContext, createInstance, getClipPreferences,
// getRegionOfDefinition, getRegionsOfInterest, getFramesNeeded, render at any
// scale 1/k, whole or in tiles, destroyInstance, unload).
//
// It is strict where plugins go wrong in practice: reading an unknown
// property or a bad index fails, images must be released (live_images()),
// output images are exactly the render window with guard values after each
// row (a write outside the window is detected), and input images are the
// last regions of interest clipped to the clip's region of definition.
#pragma once

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "ofxCore.h"
#include "ofxImageEffect.h"
#include "ofxMessage.h"
#include "ofxMultiThread.h"
#include "ofxParam.h"
#include "ofxProperty.h"

namespace gdof::ofxtest {

struct Property {
    enum Type { String, Int, Double, Pointer } type = String;
    std::vector<std::string> s;
    std::vector<int> i;
    std::vector<double> d;
    std::vector<void*> p;
    int size() const;
};

struct PropertySet {
    std::map<std::string, Property> props;
    bool has(const std::string& name) const { return props.count(name) != 0; }
    int size(const std::string& name) const;  // 0 if absent
    std::string str(const std::string& name, int index = 0) const;  // "" if absent
    int integer(const std::string& name, int index = 0, int fallback = -999) const;
    double dbl(const std::string& name, int index = 0, double fallback = -999) const;
    std::vector<std::string> strings(const std::string& name) const;
    std::vector<double> doubles(const std::string& name) const;
    void set(const std::string& name, std::vector<std::string> v);
    void set(const std::string& name, const std::string& v) { set(name, std::vector<std::string>{v}); }
    void set_i(const std::string& name, std::vector<int> v);
    void set_d(const std::string& name, std::vector<double> v);
    void set_p(const std::string& name, std::vector<void*> v);
};

struct Param {
    std::string type, name;
    PropertySet props;
    std::vector<double> d;  // double, 2D, 3D
    std::vector<int> i;     // integer, boolean, choice
    std::string s;          // string
};

struct ParamSet {
    PropertySet props;
    std::map<std::string, std::unique_ptr<Param>> params;
    std::vector<std::string> order;  // definition order
};

// Full-resolution pixels the host supplies for a clip at one frame.
struct ClipFrame {
    OfxRectI bounds{0, 0, 0, 0};  // OFX pixel coordinates at scale 1 (y up)
    std::string components = kOfxImageComponentRGBA;
    std::string depth = kOfxBitDepthFloat;  // Float, or Byte / Short (stored as float values 0..1, sent converted)
    std::string premult = kOfxImagePreMultiplied;
    std::vector<float> px;  // interleaved, bottom row first
    // How the host reduces it for render scale 1/k: the mean of each k x k
    // block ("box", colour) or its bottom-left pixel ("nearest", data passes).
    std::string filter = "box";
    int ncomp() const;
    int width() const { return bounds.x2 - bounds.x1; }
    int height() const { return bounds.y2 - bounds.y1; }
    float& at(int x, int y, int c) { return px[(std::size_t(y - bounds.y1) * std::size_t(width()) + std::size_t(x - bounds.x1)) * std::size_t(ncomp()) + std::size_t(c)]; }
    float at(int x, int y, int c) const { return px[(std::size_t(y - bounds.y1) * std::size_t(width()) + std::size_t(x - bounds.x1)) * std::size_t(ncomp()) + std::size_t(c)]; }
    static ClipFrame make(int w, int h, const std::string& components);
};

struct ImageEffect;

struct Clip {
    std::string name;
    PropertySet props;
    ImageEffect* effect = nullptr;
    std::map<int, ClipFrame> frames;  // connected when not empty
};

class Host;

struct ImageEffect {  // a descriptor or an instance
    Host* host = nullptr;
    bool instance = false;
    PropertySet props;
    ParamSet params;
    std::map<std::string, std::unique_ptr<Clip>> clips;
    std::vector<std::string> clip_order;
    // Messages.
    std::mutex mu;
    std::string persistent_type, persistent_message;
    std::vector<std::string> messages;
    // Regions of interest of the render in progress (canonical), by clip.
    std::map<std::string, OfxRectD> roi;
    // abort(): answers 1 from the abort_after-th poll on (-1: never).
    std::atomic<long> abort_polls{0};
    long abort_after = -1;
    bool honour_clip_preferences = true;
};

struct Plugin {
    OfxPlugin* ofx = nullptr;
    std::string id;
    OfxStatus load_status = kOfxStatErrUnknown;
    std::unique_ptr<ImageEffect> descriptor;
    std::map<std::string, std::unique_ptr<ImageEffect>> contexts;
};

// The output of a render: a frame buffer over the output's region of
// definition at the render scale (OFX pixels, bottom row first).
struct Rendered {
    OfxStatus status = kOfxStatErrUnknown;
    OfxRectI bounds{0, 0, 0, 0};
    int ncomp = 4;
    std::vector<float> px;
    bool wrote_outside = false;  // a guard value after a row was changed
    float at(int x, int y, int c) const {
        return px[(std::size_t(y - bounds.y1) * std::size_t(bounds.x2 - bounds.x1) + std::size_t(x - bounds.x1)) * std::size_t(ncomp) + std::size_t(c)];
    }
};

class Instance {
public:
    Instance(Host& host, Plugin& plugin, const std::string& context, int width, int height);
    ~Instance();
    ImageEffect& effect() { return *fx_; }
    OfxStatus create_status() const { return create_status_; }

    // Parameter values (as a user would set them). Unknown names or wrong
    // types throw std::runtime_error (a test bug).
    void set(const std::string& name, double v);
    void set_int(const std::string& name, int v);
    void set_bool(const std::string& name, bool v);
    void set2(const std::string& name, double x, double y);
    void set_choice(const std::string& name, const std::string& option);
    void set_string(const std::string& name, const std::string& v);
    void set3(const std::string& name, double x, double y, double z);

    void connect(const std::string& clip, const ClipFrame& img, int frame = 0);
    void disconnect(const std::string& clip);

    OfxStatus clip_preferences();  // applies them to the clips (unless !honour_clip_preferences)
    OfxStatus region_of_definition(double time, OfxPointD scale, OfxRectD& rod);
    OfxStatus regions_of_interest(double time, OfxPointD scale, const OfxRectD& roi, std::map<std::string, OfxRectD>& out);
    OfxStatus frames_needed(double time, std::map<std::string, std::vector<double>>& out);
    // Clip preferences, RoD, then per tile (pixels at `scale`; none: the
    // whole RoD) getRegionsOfInterest + render, between begin/end sequence
    // render. concurrent: tiles from several threads at once.
    Rendered render(double time, OfxPointD scale, const std::vector<OfxRectI>& tiles = {}, bool concurrent = false);
    OfxStatus destroy();

    std::string persistent_message() const { return fx_->persistent_message; }
    std::string persistent_type() const { return fx_->persistent_type; }

private:
    OfxStatus render_tile(double time, OfxPointD scale, const OfxRectI& tile, Rendered& out, std::mutex& out_mu);
    Param& param(const std::string& name, const char* type);
    Host& host_;
    Plugin& plugin_;
    std::unique_ptr<ImageEffect> fx_;
    OfxStatus create_status_ = kOfxStatErrUnknown;
    bool destroyed_ = false;
};

class Host {
public:
    Host();
    ~Host();
    Host(const Host&) = delete;
    Host& operator=(const Host&) = delete;

    // dlopen + setHost + kOfxActionLoad of every plugin. false + *error on failure.
    bool load(const std::string& binary, std::string* error);
    void unload();  // kOfxActionUnload + dlclose
    bool loaded() const { return lib_ != nullptr; }
    std::vector<std::string> plugin_ids() const;
    Plugin* plugin(const std::string& id);

    OfxStatus describe(const std::string& id);
    OfxStatus describe_in_context(const std::string& id, const std::string& context);
    std::unique_ptr<Instance> create_instance(const std::string& id, const std::string& context, int width, int height);

    // Calls a plugin's main entry.
    OfxStatus call(Plugin& p, const char* action, const void* handle, PropertySet* in, PropertySet* out);

    PropertySet props;                       // the host's own properties
    std::vector<std::string> suites_fetched;  // "OfxPropertySuite v1", ...
    unsigned num_cpus = 2;
    std::vector<std::string> withheld_suites;  // suite names fetchSuite answers null for
    int live_images() const;                 // images fetched and not yet released

    // Implementation details shared with the suite functions.
    struct Image;
    std::mutex mu;
    std::map<const void*, std::unique_ptr<Image>> images;
    OfxHost ofx_host{};

private:
    void* lib_ = nullptr;
    std::vector<std::unique_ptr<Plugin>> plugins_;
};

struct Host::Image {
    PropertySet props;
    std::vector<float> f;
    std::vector<unsigned char> bytes;
    std::vector<unsigned short> shorts;
};

}  // namespace gdof::ofxtest

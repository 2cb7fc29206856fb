// One image effect as the glue sees it: what it describes and how it answers
// the instance actions. ofx_actions.cpp maps OFX actions onto these calls,
// sets the properties every gdof effect shares, and turns any exception into
// a persistent message and a failed status (nothing escapes to the host).
#pragma once

#include <string>

#include "gdof/exec.h"
#include "ofx_properties.h"

namespace gdof::ofx {

struct RenderArgs {
    double time = 0;
    OfxPointD scale{1, 1};
    OfxRectI window{0, 0, 0, 0};  // OFX pixel coordinates at `scale`
};

// How a render runs library code: the host's CPU count (multithread suite),
// cancelled when the host aborts the render.
Exec render_exec(OfxImageEffectHandle instance);

class Effect {
public:
    virtual ~Effect() = default;
    virtual const char* label() const = 0;       // "gdof Defocus"
    virtual const char* description() const = 0;
    // Effects that read other frames of their clips (the focal stack).
    virtual bool temporal_clip_access() const { return false; }

    // Clips and parameters for a context (kOfxImageEffectContextFilter or General).
    virtual void describe_in_context(OfxImageEffectHandle descriptor, const std::string& context) = 0;
    // Sets the clip preferences in `out` (components, depth, premultiplication).
    virtual void clip_preferences(OfxImageEffectHandle instance, Props out) = 0;
    // The output's region of definition (canonical); false: the host's default.
    virtual bool region_of_definition(OfxImageEffectHandle instance, double time, OfxPointD scale, OfxRectD& rod) = 0;
    // Sets "OfxImageClipPropRoI_<clip>" in `out` for the canonical region `roi`.
    virtual void regions_of_interest(OfxImageEffectHandle instance, double time, OfxPointD scale, const OfxRectD& roi,
                                     Props out) = 0;
    // Sets "OfxImageClipPropFrameRange_<clip>" in `out`; false: the host's default.
    virtual bool frames_needed(OfxImageEffectHandle, double, Props) { return false; }
    virtual void render(OfxImageEffectHandle instance, const RenderArgs& args) = 0;
};

// The action entry of an effect (an OfxPlugin's mainEntry calls this).
OfxStatus dispatch(Effect& effect, const char* action, const void* handle, OfxPropertySetHandle in,
                   OfxPropertySetHandle out);

// Out-argument property names for a clip ("OfxImageClipPropRoI_" + name ...).
inline std::string clip_prop(const char* prefix, const char* clip) { return std::string(prefix) + clip; }

}  // namespace gdof::ofx

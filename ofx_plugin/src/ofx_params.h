// Parameters: defining them in describeInContext (typed helpers that set the
// usual properties) and reading their values at a time in the actions.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "ofx_properties.h"

namespace gdof::ofx {

// Defines parameters on an effect descriptor. Every helper sets the label,
// hint, script name (= the name) and parent group, and returns the
// parameter's property set for anything more.
class ParamDefiner {
public:
    explicit ParamDefiner(OfxImageEffectHandle descriptor);

    // Later definitions go into this group ("" = top level).
    void set_group(const std::string& group) { group_ = group; }
    Props group(const char* name, const char* label, bool open = true);
    Props number(const char* name, const char* label, double def, double min, double max, double display_min,
                 double display_max, const char* hint);
    Props integer(const char* name, const char* label, int def, int min, int max, const char* hint);
    Props boolean(const char* name, const char* label, bool def, const char* hint);
    Props choice(const char* name, const char* label, const std::vector<std::string>& options, int def,
                 const char* hint);
    Props point3(const char* name, const char* label, std::array<double, 3> def, const char* hint);
    // A point on the image, in canonical coordinates (the host's on-screen handle).
    Props point2(const char* name, const char* label, std::array<double, 2> def, const char* hint);
    // mode: kOfxParamStringIsSingleLine, ...IsMultiLine, ...IsFilePath.
    Props text(const char* name, const char* label, const char* def, const char* mode, const char* hint);

private:
    Props define(const char* type, const char* name, const char* label, const char* hint);
    OfxParamSetHandle set_ = nullptr;
    std::string group_;
};

// Reads parameter values of an effect instance at one time. Errors name the parameter.
class ParamReader {
public:
    ParamReader(OfxImageEffectHandle instance, double time);
    double number(const char* name) const;
    int integer(const char* name) const;
    bool boolean(const char* name) const;
    int choice(const char* name) const;  // option index
    // The chosen option of a choice parameter defined with `options`.
    std::string option(const char* name, const std::vector<std::string>& options) const;
    std::array<double, 3> point3(const char* name) const;
    std::array<double, 2> point2(const char* name) const;
    std::string text(const char* name) const;
    double time() const { return time_; }

private:
    OfxParamHandle handle(const char* name) const;
    OfxParamSetHandle set_ = nullptr;
    double time_ = 0;
};

}  // namespace gdof::ofx

// The state the steps run on: the Session lives for the whole run (all
// frames), a Frame for one run of the steps (one frame of a sequence). The
// settings flags give are kept in the library's own options structs.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "command.h"
#include "gdof/blur_map.h"
#include "gdof/camera.h"
#include "gdof/compositing.h"
#include "gdof/defocus.h"
#include "gdof/exec.h"
#include "gdof/focus_sweep.h"
#include "gdof/image_set.h"
#include "gdof/io/colour.h"
#include "gdof/io/io_options.h"
#include "gdof/raytrace.h"
#include "progress.h"

namespace gdof::cli {

struct StackEntry {
    ImageSet images;
    std::string source;  // file it came from ("" for results)
    // Colour space of the colour channels after --colorconvert (canonical
    // name); "" while they are in the scene-linear working space.
    std::string colorspace;
    // The depth channel --depth attached, and from which file ("": none): a
    // --depth-channel after it names another channel, which the image lacks.
    std::string attached_depth, attached_from;
};

// A parsed --blurfield (blur_state.h).
struct BlurState;

struct Session {
    GlobalOptions global;
    std::shared_ptr<const io::ColourConfig> colour;
    Progress progress;
    Stats stats;
    Exec exec;  // threads, cancel flag, progress
    // Blur fields already parsed, by path (a sequence parses each file once).
    std::map<std::string, std::shared_ptr<BlurState>> blur_cache;
};

// --render and its options (ops/render.cpp); it runs when a step comes that
// is not one of them (see Deferred).
struct PendingRender {
    std::string scene;      // pending --render ("" none)
    RenderOptions options;  // --spp, --min-spp, ..., --aovs=LIST; the blur field is set when it runs
    bool deep = false;      // --deep: a deep image (for method 3)
    bool aperture_given = false;  // --aperture (else the scene camera's aperture)
    std::string stack_spec; // --stack after --render: the next -o writes a stack
    bool pending() const { return !scene.empty(); }
};

// --composite and its options, which may come before or after it (ops/composite.cpp).
struct PendingComposite {
    std::string manifest;  // pending --composite ("" none)
    std::string surfaces, near_map, far_map;
    CompositeOptions options;  // --soft, --aovs
};

// --lightfield: the next -o writes its stack (ops/lightfield.cpp).
struct PendingLightField {
    std::string source;      // pending light-field views ("" none)
    std::string config;      // --lf
    std::string stack_spec;  // --stack (when not after --render)
};

// --depth-from-focus's modifiers (ops/focus_sweep.cpp).
struct PendingSweep {
    std::string aligned_stack;  // --aligned-stack PATTERN ("" none): the aligned frames + manifest.json
    std::vector<double> focus_distances;  // --focus-distances (a pattern's frames; empty: unknown)
    DepthFromFocusOptions options;
};

struct Frame {
    Session* session = nullptr;
    std::optional<int> frame;  // frame number when running a sequence
    std::vector<StackEntry> stack;

    // Input and output modifiers.
    std::string next_input_colorspace;  // --iscolorspace (next input only)
    io::WriteOptions output;            // -d, --compression, --ocolorspace (this and later outputs)
    bool info_on_read = false;          // --info before any input: describe each input

    // Where depth comes from (--position-channels, --depth-channel,
    // --depth-encoding ...) and the lens (--focal-length-mm ...): used by
    // --eval-blur, --diffuse and --composite.
    PositionSource source;
    LensOverrides lens;
    std::shared_ptr<BlurState> blur;  // --blurfield
    // --focus-at X,Y: the focus distance is the depth at that pixel (the thin
    // lens's, and a --blurfield refocused there).
    std::optional<std::pair<int, int>> focus_at;
    // Notes --focus-at gave on this frame: each is said once, though every
    // --probe and method that uses the focus finds it again.
    mutable std::set<std::string> focus_notes;

    // --solver, --adi-steps, --layers, --depth-cleanup; --diffuse takes its
    // source from `source`.
    DefocusOptions defocus;

    PendingRender render;
    PendingComposite composite;
    PendingLightField lightfield;
    PendingSweep sweep;

    Frame(Session& s, std::optional<int> frame_number);
    StackEntry& top(const std::string& flag);
};

// Runs one frame's steps (run.cpp). Throws CliError.
void run_steps(Session& session, const std::vector<Step>& steps, std::optional<int> frame);
// A step's arguments with the frame number put into its file names
// (#### / @ / %0Nd); a stack's -o keeps its pattern (it numbers references).
Step with_frame_number(const Step& step, const Command& command, std::optional<int> frame);

}  // namespace gdof::cli

// DefocusStats::report(): the --stats block of the defocus pipeline.
#include <iomanip>
#include <sstream>

#include "gdof/defocus.h"

namespace gdof {

std::string DefocusStats::report() const {
    std::ostringstream o;
    o << "defocus:\n";
    o << "  layers            " << layers << " (" << layers_empty << " empty, " << layers_sharp << " sharp, "
      << (layers - layers_empty - layers_sharp) << (layers_bokeh ? " spread)\n" : " diffused)\n");
    if (layers_vibrated)
        o << "  psf field         " << layers_vibrated << " layers moved, " << vibrate.samples
          << " aperture samples, largest displacement " << std::fixed << std::setprecision(2)
          << vibrate.max_displacement_px << " px, " << vibrate.splats << " splats\n";
    else if (layers_bokeh) o << "  filter            bokeh (" << layers_bokeh << " layers)\n";
    else o << "  solver            " << layers_explicit << " explicit, " << layers_adi << " adi"
           << (layers_pyramid ? ", " + std::to_string(layers_pyramid) + " on the pyramid" : std::string()) << "\n";
    o << std::fixed << std::setprecision(2);
    o << "  max blur radius   " << max_radius_px << " px\n";
    o << "  pixels diffused   " << pixels_diffused << "\n";
    o << "  pixels skipped    " << pixels_skipped << "\n";
    if (depth.pixels) o << "  " << depth.report() << "\n";
    o << std::setprecision(3);
    const std::pair<const char*, double> stages[] = {{"layers", t_layers},       {"blur map", t_blur},
                                                     {"extrapolate", t_extrapolate}, {layers_vibrated ? "vibrate" : layers_bokeh ? "spread" : "diffuse", t_diffuse},
                                                     {"composite", t_composite}};
    for (const auto& [name, t] : stages) o << "  " << std::left << std::setw(18) << (std::string("t ") + name) << std::right
                                           << std::setw(8) << t << " s\n";
    return o.str();
}

}  // namespace gdof

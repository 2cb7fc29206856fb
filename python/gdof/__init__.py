"""gdof: generalized depth of field for film post (Kosloff & Barsky).

The C++ library's calls with numpy arrays: images and deep images
(gdof.read_image -> gdof.ImageSet of gdof.Image / gdof.DeepImage, pixels as
(C, H, W) float32 views), blur fields (gdof.BlurField.parse / .read),
cameras, and the methods: gdof.defocus (method 3: diffusion or bokeh; method
4, filter="vibrate", with a gdof.PsfField),
gdof.composite (method 2), gdof.render (method 1), gdof.extract_stack
(light fields), gdof.align_sweep and gdof.depth_from_focus (photographed
focus sweeps). Errors are gdof.Error with the library's message; the GIL
is released while the library works; progress= takes a callable; Ctrl-C
stops the work and raises KeyboardInterrupt. docs/python.md has the guide.

gdof.farm turns gdof command lines into render-farm jobs (python -m gdof.farm).
"""

from ._gdof import (  # noqa: F401
    Aperture,
    BlurField,
    Camera,
    DeepImage,
    DefocusOptions,
    DefocusStats,
    DepthCleanupOptions,
    DepthDecode,
    DepthFromFocusStats,
    DiffusionOptions,
    Error,
    Image,
    ImageSet,
    LayerSplit,
    LensInfo,
    Metadata,
    PixelProbe,
    PositionSource,
    PsfField,
    Roi,
    Similarity,
    SweepAlignment,
    ThinLens,
    VibrateOptions,
    VibrateStats,
    __version__,
    align_sweep,
    composite,
    depth_from_focus,
    defocus,
    extract_stack,
    lens_at_frame,
    probe,
    read_image,
    render,
    resolve_camera,
    write_image,
)

__all__ = [
    "Aperture", "BlurField", "Camera", "DeepImage", "DefocusOptions", "DefocusStats", "DepthCleanupOptions",
    "DepthDecode", "DepthFromFocusStats", "DiffusionOptions", "Error", "Image", "ImageSet", "LayerSplit", "LensInfo", "Metadata",
    "PixelProbe", "PositionSource", "PsfField", "Roi", "Similarity", "SweepAlignment", "ThinLens", "VibrateOptions", "VibrateStats", "__version__", "align_sweep", "composite", "defocus", "depth_from_focus", "extract_stack", "lens_at_frame", "probe",
    "read_image", "render", "resolve_camera", "write_image",
]

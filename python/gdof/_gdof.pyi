"""
gdof: generalized depth of field (the C++ library's bindings; import gdof)
"""

from collections.abc import Iterator, Sequence
from typing import Annotated, overload

import numpy
from numpy.typing import NDArray

from gdof import Error as Error


class Roi:
    """
    A half-open pixel rectangle [x0, x1) x [y0, y1) in absolute coordinates
    """

    @overload
    def __init__(self) -> None: ...

    @overload
    def __init__(self, x0: int, y0: int, x1: int, y1: int) -> None: ...

    @property
    def x0(self) -> int: ...

    @x0.setter
    def x0(self, arg: int, /) -> None: ...

    @property
    def y0(self) -> int: ...

    @y0.setter
    def y0(self, arg: int, /) -> None: ...

    @property
    def x1(self) -> int: ...

    @x1.setter
    def x1(self, arg: int, /) -> None: ...

    @property
    def y1(self) -> int: ...

    @y1.setter
    def y1(self, arg: int, /) -> None: ...

    @property
    def width(self) -> int: ...

    @property
    def height(self) -> int: ...

    @property
    def empty(self) -> bool: ...

    def __eq__(self, arg: object, /) -> bool: ...

    def __iter__(self) -> Iterator: ...

    def __repr__(self) -> str: ...

class Metadata:
    """
    Header attributes with their file types: md['focalLength'] -> 50.0; md['worldToCamera'] -> 4x4 rows; md[name] = value (str, int, float, numbers, 4x4 matrix)
    """

    def __init__(self) -> None: ...

    def __getitem__(self, arg: str, /) -> object: ...

    def __setitem__(self, arg0: str, arg1: object, /) -> None: ...

    def set(self, name: str, value: object, type: str) -> None:
        """
        set with an explicit file type ('float', 'int', 'matrix', 'float[2]', ...)
        """

    def __delitem__(self, arg: str, /) -> None: ...

    def __contains__(self, arg: str, /) -> bool: ...

    def __len__(self) -> int: ...

    def keys(self) -> list[str]: ...

    def __iter__(self) -> Iterator: ...

    def type(self, arg: str, /) -> str:
        """the attribute's file type"""

    def to_dict(self) -> dict: ...

class Image:
    """
    A flat image: named channels over a data window, a display window, metadata. pixels is a (C, H, W) float32 view of the library's float planes.
    """

    def __init__(self, channels: object, data_window: object, display_window: object | None = None) -> None:
        """zero-filled; channels are names or (name, type) pairs"""

    @staticmethod
    def from_array(pixels: Annotated[NDArray[numpy.float32], dict(shape=(None, None, None), order='C', device='cpu')], channels: object, data_window: object | None = None, display_window: object | None = None) -> Image:
        """
        an image from a (C, H, W) array (copied), float channels named by `channels`
        """

    @property
    def width(self) -> int: ...

    @property
    def height(self) -> int: ...

    @property
    def pixels(self) -> Annotated[NDArray[numpy.float32], dict(shape=(None, None, None))]:
        """
        (C, H, W) float32 view of the float (and half) channels, in channel order (pixel_channels); uint channels (ids) are read with channel()
        """

    @property
    def pixel_channels(self) -> list[str]:
        """the names of pixels' planes"""

    def channel(self, channel: object) -> object:
        """
        (H, W) view of one channel by name or index: float32, or uint32 for a uint channel
        """

    def rename_channel(self, arg0: object, arg1: str, /) -> None: ...

    def attach_depth(self, depth: Image, channel: object | None = None, name: str = 'Z') -> None:
        """
        --depth FILE: puts a depth map's channel (`channel` by name or index; default the one named `name`, else the first) into this plate as channel `name` (default Z); the sizes must match
        """

    def __repr__(self) -> str: ...

    @property
    def channels(self) -> list:
        """[(name, type)], type 'half', 'float' or 'uint'"""

    @property
    def channel_names(self) -> list[str]: ...

    def channel_index(self, arg: str, /) -> int:
        """index of a channel by name, -1 if absent"""

    def set_channel_type(self, arg0: object, arg1: str, /) -> None:
        """half <-> float (the storage type in files; pixels stay float32)"""

    @property
    def data_window(self) -> Roi: ...

    @property
    def display_window(self) -> Roi: ...

    @display_window.setter
    def display_window(self, arg: object, /) -> None: ...

    @property
    def metadata(self) -> Metadata: ...

    @metadata.setter
    def metadata(self, arg: Metadata, /) -> None: ...

    @property
    def name(self) -> str:
        """EXR part name"""

    @name.setter
    def name(self, arg: str, /) -> None: ...

    @property
    def view(self) -> str:
        """EXR view name ('left')"""

    @view.setter
    def view(self, arg: str, /) -> None: ...

    def copy(self) -> Image: ...

class DeepImage:
    """
    A deep image: each pixel a list of samples; samples(c) is a view of one channel's samples, pixel after pixel (sample_offsets gives each pixel's first)
    """

    def __init__(self, channels: object, data_window: object, display_window: object | None = None, sample_counts: object | None = None) -> None:
        """zeroed samples, `sample_counts` (H, W) per pixel (default 0)"""

    @property
    def total_samples(self) -> int: ...

    @property
    def sample_counts(self) -> Annotated[NDArray[numpy.uint32], dict(shape=(None, None), writable=False)]:
        """(H, W) uint32, read-only"""

    @property
    def sample_offsets(self) -> list[int]:
        """each pixel's first sample (row-major pixels), a list"""

    def samples(self, channel: object) -> object:
        """one channel's samples, pixel after pixel: a float32 (or uint32) view"""

    @property
    def z_channel(self) -> int: ...

    def __repr__(self) -> str: ...

    @property
    def channels(self) -> list:
        """[(name, type)], type 'half', 'float' or 'uint'"""

    @property
    def channel_names(self) -> list[str]: ...

    def channel_index(self, arg: str, /) -> int:
        """index of a channel by name, -1 if absent"""

    def set_channel_type(self, arg0: object, arg1: str, /) -> None:
        """half <-> float (the storage type in files; pixels stay float32)"""

    @property
    def data_window(self) -> Roi: ...

    @property
    def display_window(self) -> Roi: ...

    @display_window.setter
    def display_window(self, arg: object, /) -> None: ...

    @property
    def metadata(self) -> Metadata: ...

    @metadata.setter
    def metadata(self, arg: Metadata, /) -> None: ...

    @property
    def name(self) -> str:
        """EXR part name"""

    @name.setter
    def name(self, arg: str, /) -> None: ...

    @property
    def view(self) -> str:
        """EXR view name ('left')"""

    @view.setter
    def view(self, arg: str, /) -> None: ...

    def copy(self) -> DeepImage: ...

class ImageSet:
    """
    The parts of a file (EXR multipart), each a gdof.Image or gdof.DeepImage. Its parts are references into the set (no copy); the set's structure does not change after it is made.
    """

    def __init__(self, parts: object) -> None:
        """a set from images (copied)"""

    def __len__(self) -> int: ...

    def __getitem__(self, arg: int, /) -> object: ...

    def is_deep(self, arg: int, /) -> bool: ...

    def views(self) -> list[str]:
        """the distinct view names of the parts"""

    def select_view(self, arg: str, /) -> ImageSet:
        """the parts of one view (and those of no view), a new set"""

    def select_parts(self, arg: str, /) -> ImageSet:
        """parts by name or index ('beauty,depth', '0,2'), a new set"""

    def __repr__(self) -> str: ...

def read_image(path: str, linearize: bool = True, colorspace: str = '') -> ImageSet:
    """
    Reads every part of an image file (EXR flat, multipart, deep; PNG, JPEG, TIFF, ...) as a gdof.ImageSet; colour to scene-linear unless linearize=False.
    """

def write_image(path: str, images: object, pixel_type: str = '', compression: str = '', colorspace: str = '') -> None:
    """
    Writes a gdof.ImageSet, an Image, a DeepImage or a list of them (several: EXR multipart); atomically (a temporary file renamed: never a partial file).
    """

class ThinLens:
    """A thin lens: CoC radii in output pixels"""

    def __init__(self, focal_length_mm: float = 50.0, f_number: float = 2.8, focus_distance: float = 2.0, sensor_width_mm: float = 36.0, image_width_px: float = 1920.0, scene_unit_mm: float = 1000.0) -> None: ...

    @property
    def focal_length_mm(self) -> float: ...

    @focal_length_mm.setter
    def focal_length_mm(self, arg: float, /) -> None: ...

    @property
    def f_number(self) -> float: ...

    @f_number.setter
    def f_number(self, arg: float, /) -> None: ...

    @property
    def focus_distance(self) -> float: ...

    @focus_distance.setter
    def focus_distance(self, arg: float, /) -> None: ...

    @property
    def sensor_width_mm(self) -> float: ...

    @sensor_width_mm.setter
    def sensor_width_mm(self, arg: float, /) -> None: ...

    @property
    def image_width_px(self) -> float: ...

    @image_width_px.setter
    def image_width_px(self, arg: float, /) -> None: ...

    @property
    def scene_unit_mm(self) -> float: ...

    @scene_unit_mm.setter
    def scene_unit_mm(self, arg: float, /) -> None: ...

    def validate(self) -> None: ...

    def coc_radius_px(self, depth: float) -> float: ...

    def hyperfocal_distance(self, coc_radius_px: float) -> float: ...

    def dof_limits(self, coc_radius_px: float) -> tuple:
        """(near, far) where the CoC radius is coc_radius_px"""

class LensInfo:
    """The lens data a camera carries (NaN = unknown)"""

    def __init__(self) -> None: ...

    @property
    def focal_length_mm(self) -> float: ...

    @focal_length_mm.setter
    def focal_length_mm(self, arg: float, /) -> None: ...

    @property
    def sensor_width_mm(self) -> float: ...

    @sensor_width_mm.setter
    def sensor_width_mm(self, arg: float, /) -> None: ...

    @property
    def f_number(self) -> float: ...

    @f_number.setter
    def f_number(self, arg: float, /) -> None: ...

    @property
    def focus_distance(self) -> float: ...

    @focus_distance.setter
    def focus_distance(self, arg: float, /) -> None: ...

    @property
    def scene_unit_mm(self) -> float: ...

    @scene_unit_mm.setter
    def scene_unit_mm(self, arg: float, /) -> None: ...

    @property
    def complete(self) -> bool: ...

class Camera:
    """Projection, view and lens of an image (docs/camera.md)"""

    @staticmethod
    def from_metadata(metadata: Metadata, display_window: object) -> Camera:
        """from EXR attributes (worldToCamera, worldToNDC, lens)"""

    @staticmethod
    def look_at(position: object, look_at: object, up: object = (0, 1, 0), focal_length_mm: float = 50.0, sensor_width_mm: float = 36.0, display_window: object = (0, 0, 1920, 1080), f_number: float = float('nan'), focus_distance: float = float('nan'), scene_unit_mm: float = 1000.0) -> Camera:
        """a perspective camera (right-handed world, as the scene JSON's camera)"""

    def to_metadata(self, metadata: Metadata) -> None:
        """writes worldToCamera, worldToNDC and the lens"""

    def project(self, points: object) -> object:
        """(N, 3) world points -> (N, 3) pixel x, y (centres at +0.5) and depth"""

    def unproject(self, x: float, y: float, depth: float) -> object: ...

    @property
    def world_to_camera(self) -> object: ...

    @property
    def world_to_ndc(self) -> object: ...

    @property
    def display_window(self) -> Roi: ...

    @property
    def position(self) -> object: ...

    @property
    def forward(self) -> object: ...

    @property
    def focal_length_px(self) -> float: ...

    @property
    def hfov_deg(self) -> float: ...

    @property
    def lens(self) -> LensInfo: ...

    @lens.setter
    def lens(self, arg: LensInfo, /) -> None: ...

    def thin_lens(self) -> ThinLens:
        """
        the thin lens of the camera's lens data (an error naming what is missing)
        """

def resolve_camera(metadata: Metadata, display_window: object, *, focal_length_mm: float | None = None, sensor_width_mm: float | None = None, f_number: float | None = None, focus_distance: float | None = None, scene_unit_mm: float | None = None) -> Camera:
    """
    The camera of an image's metadata with lens overrides (the CLI's --focal-length-mm ...); without camera attributes, a camera at the origin looking down +z when a focal length is given.
    """

def lens_at_frame(path: str, frame: float) -> dict:
    """
    --lens-table FILE for one frame: the lens keywords (focus_distance, f_number, focal_length_mm, sensor_width_mm) the table gives that frame, as a dict for defocus(..., **lens): the frame's row, else interpolated between rows (focus in 1/distance), else the nearest end's.
    """

class BlurField:
    """
    The blur field B(x) (docs/blur_field.md): BlurField.parse(dict or JSON text), BlurField.read(path), BlurField.from_thin_lens(lens)
    """

    def __init__(self) -> None:
        """a field that is 0 everywhere"""

    @staticmethod
    def parse(spec: object, base_dir: str = '') -> BlurField:
        """
        from a dict ({'blurfield': {...}}) or JSON text; image_map paths relative to base_dir
        """

    @staticmethod
    def read(path: str) -> BlurField:
        """from a JSON file"""

    @staticmethod
    def from_thin_lens(lens: ThinLens) -> BlurField: ...

    def evaluate(self, camera: Camera, points: object) -> object:
        """B at (N, 3) world points: (N,) float32 radii in output pixels"""

    def evaluate_pixel(self, camera: Camera, x: float, y: float, depth: float) -> float:
        """B at continuous pixel (x, y) (centres at +0.5) and depth"""

    def refocused(self, focus_distance: float) -> BlurField: ...

    @property
    def max_radius(self) -> float: ...

    @property
    def depth_only(self) -> bool: ...

    def describe(self) -> str: ...

    def __repr__(self) -> str: ...

class PsfField:
    """
    Method 4's PSF field (docs/psf_field.md): for a point and an aperture sample, a displacement. PsfField() is the defocus field; PsfField.parse(dict or JSON text), PsfField.read(path)
    """

    def __init__(self) -> None:
        """the defocus field: B(x) times the aperture sample"""

    @staticmethod
    def parse(spec: object, base_dir: str = '') -> PsfField:
        """
        from a dict ({'psf_field': {...}}) or JSON text; image_map paths relative to base_dir
        """

    @staticmethod
    def read(path: str) -> PsfField:
        """from a JSON file"""

    @property
    def samples(self) -> int:
        """aperture samples the file asks for (0: automatic)"""

    @property
    def moves_depth(self) -> bool:
        """True when a part moves points along their rays"""

    def describe(self) -> str: ...

    def __repr__(self) -> str: ...

class VibrateOptions:
    """The vibrate filter's sampling (psf_field.h)"""

    def __init__(self) -> None: ...

    @property
    def samples(self) -> int:
        """aperture samples; 0: the field's, else automatic"""

    @samples.setter
    def samples(self, arg: int, /) -> None: ...

    @property
    def seed(self) -> int:
        """of the samples' jitter"""

    @seed.setter
    def seed(self, arg: int, /) -> None: ...

    @property
    def prefilter(self) -> float:
        """each sample's splat: sigma = prefilter * sample spacing"""

    @prefilter.setter
    def prefilter(self, arg: float, /) -> None: ...

class VibrateStats:
    """What the vibrate filter did"""

    def __init__(self) -> None: ...

    @property
    def samples(self) -> int: ...

    @property
    def spacing(self) -> float: ...

    @property
    def max_displacement_px(self) -> float: ...

    @property
    def splats(self) -> int: ...

class DiffusionOptions:
    def __init__(self) -> None: ...

    @property
    def solver(self) -> str:
        """auto, explicit or adi"""

    @solver.setter
    def solver(self, arg: str, /) -> None: ...

    @property
    def adi_steps(self) -> int: ...

    @adi_steps.setter
    def adi_steps(self, arg: int, /) -> None: ...

    @property
    def explicit_safety(self) -> float: ...

    @explicit_safety.setter
    def explicit_safety(self, arg: float, /) -> None: ...

    @property
    def max_radius(self) -> float: ...

    @max_radius.setter
    def max_radius(self, arg: float, /) -> None: ...

    @property
    def pyramid(self) -> bool: ...

    @pyramid.setter
    def pyramid(self, arg: bool, /) -> None: ...

class LayerSplit:
    """
    How defocus splits its input into layers; LayerSplit.parse('auto:16:blur=3')
    """

    def __init__(self) -> None: ...

    @staticmethod
    def parse(text: str) -> LayerSplit: ...

    @property
    def mode(self) -> str: ...

    @property
    def count(self) -> int: ...

    @count.setter
    def count(self, arg: int, /) -> None: ...

    @property
    def max_layers(self) -> int: ...

    @max_layers.setter
    def max_layers(self, arg: int, /) -> None: ...

    @property
    def blur_step(self) -> float: ...

    @blur_step.setter
    def blur_step(self, arg: float, /) -> None: ...

    @property
    def id_channel(self) -> str: ...

    @id_channel.setter
    def id_channel(self, arg: str, /) -> None: ...

class DepthDecode:
    """How stored depth values become metric depth (camera.h)"""

    def __init__(self) -> None: ...

    @property
    def encoding(self) -> str: ...

    @encoding.setter
    def encoding(self, arg: str, /) -> None: ...

    @property
    def scale(self) -> float: ...

    @scale.setter
    def scale(self, arg: float, /) -> None: ...

    @property
    def near(self) -> float: ...

    @near.setter
    def near(self, arg: float, /) -> None: ...

    @property
    def far(self) -> float: ...

    @far.setter
    def far(self, arg: float, /) -> None: ...

    @property
    def flip(self) -> bool: ...

    @flip.setter
    def flip(self, arg: bool, /) -> None: ...

    @property
    def range(self) -> bool: ...

    @range.setter
    def range(self, arg: bool, /) -> None: ...

    @property
    def invalid(self) -> float: ...

    @invalid.setter
    def invalid(self, arg: float, /) -> None: ...

    @property
    def invalid_value(self) -> float | None: ...

    @invalid_value.setter
    def invalid_value(self, arg: float | None, /) -> None: ...

    @property
    def max_depth(self) -> float: ...

    @max_depth.setter
    def max_depth(self, arg: float, /) -> None: ...

    @property
    def baseline(self) -> float: ...

    @baseline.setter
    def baseline(self, arg: float, /) -> None: ...

class PositionSource:
    """Where a pixel's world position or depth comes from"""

    def __init__(self) -> None: ...

    @property
    def position_channels(self) -> str: ...

    @position_channels.setter
    def position_channels(self, arg: str, /) -> None: ...

    @property
    def depth_channel(self) -> str: ...

    @depth_channel.setter
    def depth_channel(self, arg: str, /) -> None: ...

    @property
    def depth_decode(self) -> DepthDecode: ...

    @depth_decode.setter
    def depth_decode(self, arg: DepthDecode, /) -> None: ...

class DepthCleanupOptions:
    """Plate depth repair (plate.h)"""

    def __init__(self) -> None: ...

    @property
    def remove_speckles(self) -> bool: ...

    @remove_speckles.setter
    def remove_speckles(self, arg: bool, /) -> None: ...

    @property
    def mixed_pixels(self) -> bool: ...

    @mixed_pixels.setter
    def mixed_pixels(self, arg: bool, /) -> None: ...

    @property
    def smooth_noise(self) -> bool: ...

    @smooth_noise.setter
    def smooth_noise(self, arg: bool, /) -> None: ...

    @property
    def continuity(self) -> float: ...

    @continuity.setter
    def continuity(self, arg: float, /) -> None: ...

    @property
    def speckle_px(self) -> int: ...

    @speckle_px.setter
    def speckle_px(self, arg: int, /) -> None: ...

    @property
    def mixed_step(self) -> float: ...

    @mixed_step.setter
    def mixed_step(self, arg: float, /) -> None: ...

class Aperture:
    """
    The iris (aperture.h): Aperture.parse('polygon:6:15,roundness=0.2'); an image kernel is given as `image` (a gdof.Image)
    """

    def __init__(self) -> None: ...

    @staticmethod
    def parse(spec: str) -> Aperture: ...

    @property
    def kind(self) -> str: ...

    @property
    def blades(self) -> int: ...

    @blades.setter
    def blades(self, arg: int, /) -> None: ...

    @property
    def rotation_deg(self) -> float: ...

    @rotation_deg.setter
    def rotation_deg(self, arg: float, /) -> None: ...

    @property
    def roundness(self) -> float: ...

    @roundness.setter
    def roundness(self, arg: float, /) -> None: ...

    @property
    def squeeze(self) -> float: ...

    @squeeze.setter
    def squeeze(self, arg: float, /) -> None: ...

    @property
    def cats_eye(self) -> float: ...

    @cats_eye.setter
    def cats_eye(self, arg: float, /) -> None: ...

    @property
    def image(self) -> Image: ...

    @image.setter
    def image(self, arg: Image, /) -> None: ...

    def validate(self) -> None: ...

    def __str__(self) -> str: ...

class DefocusOptions:
    """Every setting of defocus() (defocus.h), as the C++ struct"""

    def __init__(self) -> None: ...

    @property
    def filter(self) -> str:
        """diffusion, bokeh or vibrate"""

    @filter.setter
    def filter(self, arg: str, /) -> None: ...

    @property
    def aperture(self) -> Aperture: ...

    @aperture.setter
    def aperture(self, arg: object, /) -> None: ...

    @property
    def psf_field(self) -> PsfField:
        """vibrate: a PsfField, the path of its file or its dict"""

    @psf_field.setter
    def psf_field(self, arg: object, /) -> None: ...

    @property
    def vibrate(self) -> VibrateOptions: ...

    @vibrate.setter
    def vibrate(self, arg: VibrateOptions, /) -> None: ...

    @property
    def diffusion(self) -> DiffusionOptions: ...

    @diffusion.setter
    def diffusion(self, arg: DiffusionOptions, /) -> None: ...

    @property
    def split(self) -> LayerSplit:
        """a LayerSplit or its text"""

    @split.setter
    def split(self, arg: object, /) -> None: ...

    @property
    def source(self) -> PositionSource: ...

    @source.setter
    def source(self, arg: PositionSource, /) -> None: ...

    @property
    def cleanup(self) -> DepthCleanupOptions: ...

    @cleanup.setter
    def cleanup(self, arg: DepthCleanupOptions, /) -> None: ...

    @property
    def roi(self) -> Roi: ...

    @roi.setter
    def roi(self, arg: object, /) -> None: ...

class DefocusStats:
    """What defocus() did (pass one as stats= to fill it)"""

    def __init__(self) -> None: ...

    @property
    def layers(self) -> int: ...

    @property
    def layers_empty(self) -> int: ...

    @property
    def layers_sharp(self) -> int: ...

    @property
    def layers_explicit(self) -> int: ...

    @property
    def layers_adi(self) -> int: ...

    @property
    def layers_bokeh(self) -> int: ...

    @property
    def layers_pyramid(self) -> int: ...

    @property
    def layers_vibrated(self) -> int: ...

    @property
    def vibrate(self) -> VibrateStats: ...

    @property
    def max_radius_px(self) -> float: ...

    def report(self) -> str: ...

def defocus(input: ImageSet | Image | DeepImage | list[Image | DeepImage], blurfield: BlurField | None = None, camera: Camera | None = None, *, options: DefocusOptions | None = None, stats: DefocusStats | None = None, progress: object | None = None, threads: int = 0, filter: str | None = None, aperture: Aperture | str | None = None, psf_field: PsfField | dict | str | None = None, psf_samples: int | None = None, solver: str | None = None, adi_steps: int | None = None, explicit_safety: float | None = None, max_radius: float | None = None, pyramid: bool | None = None, layers: LayerSplit | str | int | None = None, position_channels: str | None = None, depth_channel: str | None = None, depth_encoding: str | None = None, depth_scale: float | None = None, depth_near: float | None = None, depth_far: float | None = None, depth_invalid: str | float | None = None, depth_invalid_value: float | None = None, depth_max: float | None = None, baseline: float | None = None, depth_range: bool | None = None, remove_speckles: bool | None = None, smooth_noise: bool | None = None, mixed_pixels: bool | None = None, roi: Roi | tuple[int, int, int, int] | None = None, focal_length_mm: float | None = None, sensor_width_mm: float | None = None, f_number: float | None = None, focus_distance: float | None = None, scene_unit_mm: float | None = None, focus_at: tuple[int, int] | None = None) -> ImageSet:
    """
    Method 3: defocuses an ImageSet (deep, multipart, or RGBA + depth; an Image or list is copied in) into one flat part: R, G, B, A. blurfield defaults to the camera's thin lens, camera to the input's (resolve_camera with the lens keywords). Keywords: the CLI's flags without dashes; filter='bokeh' is --bokeh, filter='vibrate' --vibrate (method 4, with psf_field= and psf_samples=); focus_at=(x, y) is --focus-at X,Y.
    """

class PixelProbe:
    """What probe() finds at a pixel (plate.h); NaN where unknown"""

    @property
    def x(self) -> int: ...

    @property
    def y(self) -> int: ...

    @property
    def depth(self) -> float:
        """median depth of the 5x5 pixels around (+inf: sky)"""

    @property
    def position(self) -> tuple:
        """world position (NaN without a camera)"""

    @property
    def blur_px(self) -> float:
        """blur radius in pixels (NaN without a camera and a lens or field)"""

    @property
    def mixed(self) -> bool:
        """
        a silhouette pixel the defocus splits into a foreground and a background part (step 4's only with a lens or field)
        """

    @property
    def fg_share(self) -> float:
        """a split pixel's foreground share (else NaN)"""

    @property
    def fg_depth(self) -> float:
        """a split pixel's foreground depth (else NaN)"""

    @property
    def bg_depth(self) -> float:
        """a split pixel's background depth (else NaN)"""

    @property
    def fg_blur_px(self) -> float:
        """a split pixel's foreground blur radius (else NaN)"""

    @property
    def bg_blur_px(self) -> float:
        """a split pixel's background blur radius (else NaN)"""

    def __repr__(self) -> str: ...

def probe(input: ImageSet | Image | list[Image | DeepImage], x: int, y: int, blurfield: BlurField | None = None, camera: Camera | None = None, *, position_channels: str | None = None, depth_channel: str | None = None, depth_encoding: str | None = None, depth_scale: float | None = None, depth_near: float | None = None, depth_far: float | None = None, depth_invalid: str | float | None = None, depth_invalid_value: float | None = None, depth_max: float | None = None, baseline: float | None = None, depth_range: bool | None = None, remove_speckles: bool | None = None, smooth_noise: bool | None = None, mixed_pixels: bool | None = None, focal_length_mm: float | None = None, sensor_width_mm: float | None = None, f_number: float | None = None, focus_distance: float | None = None, scene_unit_mm: float | None = None, focus_at: tuple[int, int] | None = None) -> PixelProbe:
    """
    --probe X,Y: depth, world position and blur at pixel (x, y) of the input's first flat part, its depth decoded and cleaned as defocus() does (the same keywords). Needs no lens: without a focal length only the depth, without an f-number and focus distance no blur (NaN).
    """

def composite(manifest: str, *, surfaces: object | None = None, near_map: Image | None = None, far_map: Image | None = None, image: Image | None = None, blurfield: BlurField | None = None, camera: Camera | None = None, soft: int = 1, aovs: bool = False, progress: object | None = None, threads: int = 0) -> Image:
    """
    Method 2: each pixel from the stack reference (manifest.json) whose near/far best matches the desired focus: surfaces (a file, dict or JSON text), near_map and far_map (Images), or the blur field along the rays of `image` (Z or P; blurfield defaults to its camera's thin lens). soft=K blends the best K.
    """

def render(scene: str, blurfield: BlurField | None = None, *, spp: int = 64, min_spp: int = 16, adaptive_threshold: float = 0.01, pinhole: bool = False, straight_thin_lens: bool = False, light_samples: int = 2, seed: int = 0, aovs: str = 'all', aperture: object | None = None, deep: bool = False, progress: object | None = None, threads: int = 0) -> object:
    """
    Method 1: renders a scene JSON (docs/scene.md) with its camera, or the blurfield's nonlinear rays; an Image (beauty + AOVs), or a DeepImage with deep=True.
    """

def extract_stack(views: str, stack: object, lf: object | None = None, *, progress: object | None = None, threads: int = 0) -> tuple:
    """
    A focus/aperture stack from light-field views ('views/%02d_%02d.png' or a Stanford-archive folder): stack and lf are the CLI's --stack and --lf JSON (paths, or dicts). Returns (images, manifest JSON text; its file names are empty: write the images and set them).
    """

class Similarity:
    """
    A frame-to-frame map: x' = a x - b y + tx, y' = b x + a y + ty (positions from the data window's corner, pixel centres at +0.5)
    """

    def __init__(self) -> None: ...

    @property
    def a(self) -> float: ...

    @a.setter
    def a(self, arg: float, /) -> None: ...

    @property
    def b(self) -> float: ...

    @b.setter
    def b(self, arg: float, /) -> None: ...

    @property
    def tx(self) -> float: ...

    @tx.setter
    def tx(self, arg: float, /) -> None: ...

    @property
    def ty(self) -> float: ...

    @ty.setter
    def ty(self, arg: float, /) -> None: ...

    @property
    def scale(self) -> float: ...

    @property
    def rotation_degrees(self) -> float: ...

    def apply(self, x: float, y: float) -> tuple: ...

    def __repr__(self) -> str: ...

class SweepAlignment:
    """What align_sweep() found (focus_sweep.h)"""

    @property
    def reference(self) -> int:
        """the frame the others are aligned to (from 0)"""

    @property
    def maps(self) -> list[Similarity]:
        """per frame: reference pixel -> that frame's pixel"""

    @property
    def residual_before(self) -> list[float]: ...

    @property
    def residual_after(self) -> list[float]: ...

    @property
    def common(self) -> Roi:
        """the pixels every frame sees"""

    def report(self) -> str: ...

    def __repr__(self) -> str: ...

class DepthFromFocusStats:
    @property
    def pixels(self) -> int: ...

    @property
    def holes(self) -> int: ...

    @property
    def outliers(self) -> int: ...

    def report(self) -> str: ...

    def __repr__(self) -> str: ...

def align_sweep(frames: Sequence[Image], *, progress: object | None = None, threads: int = 0) -> tuple:
    """
    Aligns a focus sweep's frames (a list of gdof.Image, one size) to the middle one: a similarity per frame, chained from neighbour to neighbour. Returns (aligned frames, SweepAlignment).
    """

def depth_from_focus(frames: Sequence[Image], focus_distances: Sequence[float] | None = None, *, align: bool = True, window_radius: int = 4, min_peak_ratio: float = 3.0, progress: object | None = None, threads: int = 0) -> tuple:
    """
    Depth from focus (the CLI's --depth-from-focus): frames in sweep order, aligned first unless align=False, and their focus distances (else the frame index from 1 is the depth). Returns (plate, DepthFromFocusStats): the all-in-focus R, G, B, A with Z, focus.index and focus.confidence.
    """

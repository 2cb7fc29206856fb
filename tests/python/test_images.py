"""Images and deep images through files and numpy: round trips keep
channels, types, windows, metadata and every bit; arrays are views."""

import numpy as np
import pytest
from conftest import same_bits

import gdof


def test_flat_round_trip_keeps_windows_types_metadata(tmp_path):
    rng = np.random.default_rng(7)
    pixels = rng.standard_normal((4, 5, 7)).astype(np.float32)
    img = gdof.Image.from_array(pixels, ["R", "G", "B", "Z"], data_window=(-2, 3, 5, 8), display_window=(0, 0, 4, 6))
    img.set_channel_type("R", "half")
    img.metadata["focalLength"] = 35.0
    img.metadata["frame"] = 12
    img.metadata["owner"] = "gdof test"
    m = np.arange(16, dtype=float).reshape(4, 4)
    img.metadata["worldToCamera"] = m
    img.metadata.set("pair", [1.5, 2.5], "float[2]")
    path = tmp_path / "flat.exr"
    gdof.write_image(str(path), img)
    back = gdof.read_image(str(path))[0]
    assert back.channels == [("R", "half"), ("G", "float"), ("B", "float"), ("Z", "float")]
    assert back.data_window == (-2, 3, 5, 8) and back.display_window == gdof.Roi(0, 0, 4, 6)
    assert same_bits(back.pixels[1:], pixels[1:])
    assert same_bits(back.channel("R"), pixels[0].astype(np.float16).astype(np.float32))
    md = back.metadata
    assert md["focalLength"] == 35.0 and md["frame"] == 12 and md["owner"] == "gdof test"
    assert md.type("worldToCamera") == "matrix" and np.array_equal(np.array(md["worldToCamera"]), m)
    assert md["pair"] == [1.5, 2.5] and md.type("pair") == "float[2]"


def test_uint_channel_and_multipart_round_trip(tmp_path):
    a = gdof.Image([("R", "float"), ("id", "uint")], (0, 0, 3, 2))
    a.channel("R")[:] = [[1, 2, 3], [4, 5, 6]]
    a.channel("id")[:] = [[7, 8, 9], [10, 11, 4000000000]]
    a.name = "beauty"
    b = gdof.Image(["Z"], (0, 0, 3, 2))
    b.channel("Z")[:] = 2.5
    b.name = "depth"
    path = tmp_path / "parts.exr"
    gdof.write_image(str(path), [a, b])
    back = gdof.read_image(str(path))
    assert len(back) == 2 and back[0].name == "beauty" and back[1].name == "depth"
    assert back[0].channel("id").dtype == np.uint32 and back[0].channel("id")[1, 2] == 4000000000
    assert same_bits(back[0].channel("R"), a.channel("R")) and np.all(back[1].channel("Z") == 2.5)
    assert back[0].pixel_channels == ["R"]


def test_deep_round_trip(tmp_path):
    counts = np.array([[0, 1, 2], [3, 0, 1]], np.uint32)
    d = gdof.DeepImage(["R", "G", "B", "A", "Z"], (10, 20, 13, 22), sample_counts=counts)
    assert d.total_samples == 7 and same_bits(d.sample_counts, counts)
    rng = np.random.default_rng(3)
    for c in d.channel_names:
        d.samples(c)[:] = rng.uniform(0.1, 5.0, 7).astype(np.float32)
    path = tmp_path / "deep.exr"
    gdof.write_image(str(path), d)
    back = gdof.read_image(str(path))
    assert back.is_deep(0)
    bd = back[0]
    assert bd.data_window == (10, 20, 13, 22) and same_bits(bd.sample_counts, counts)
    for c in d.channel_names:
        assert same_bits(bd.samples(c), d.samples(c)), c
    assert bd.sample_offsets == [0, 0, 1, 3, 6, 6]


def test_arrays_are_views_of_the_image():
    img = gdof.Image(["R", "G"], (0, 0, 4, 3))
    p = img.pixels
    p[1, 2, 3] = 9.0
    assert img.channel("G")[2, 3] == 9.0
    assert np.shares_memory(p, img.channel(1))
    del img  # the array keeps the image alive
    assert p[1, 2, 3] == 9.0


def test_image_set_parts_are_references():
    s = gdof.ImageSet([gdof.Image(["R"], (0, 0, 2, 2))])
    s[0].channel("R")[:] = 3.0
    s[0].metadata["x"] = 1.0
    assert np.all(s[0].pixels == 3.0) and s[0].metadata["x"] == 1.0


def test_bad_arguments_are_errors():
    with pytest.raises(gdof.Error, match="channel 'Q' not found"):
        gdof.Image(["R"], (0, 0, 2, 2)).channel("Q")
    with pytest.raises(gdof.Error, match="2 channel names for 3 planes"):
        gdof.Image.from_array(np.zeros((3, 2, 2), np.float32), ["R", "G"])
    with pytest.raises(gdof.Error, match="sample_counts"):
        gdof.DeepImage(["Z"], (0, 0, 2, 2), sample_counts=[1, 2, 3])

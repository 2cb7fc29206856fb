"""Shared fixtures of the Python tests: the built tools (from the environment
ctest or tests/python/pip_install.sh sets), generated inputs, and CLI runs."""

import os
import subprocess
from pathlib import Path

import pytest

import gdof

SOURCE = Path(os.environ.get("GDOF_SOURCE_DIR", Path(__file__).resolve().parents[2]))


def tool(name):
    """A built executable named by an environment variable (GDOF_CLI, ...)."""
    path = os.environ.get(name, "")
    if not path or not Path(path).exists():
        message = f"{name} is not set to a built executable"
        if os.environ.get("CI") == "true":
            pytest.fail("CI=true, so this may not skip: " + message)
        pytest.skip(message)
    return path


@pytest.fixture(scope="session")
def cli():
    return tool("GDOF_CLI")


def run_cli(cli, *args, check=True):
    """Runs gdof; returns the CompletedProcess (stdout and stderr as text)."""
    r = subprocess.run([cli, *map(str, args)], capture_output=True, text=True)
    if check and r.returncode != 0:
        raise AssertionError(f"gdof {' '.join(map(str, args))} failed ({r.returncode}):\n{r.stderr}")
    return r


@pytest.fixture(scope="session")
def scene(tmp_path_factory):
    """The generated example scene, small: (flat.exr, deep.exr)."""
    make = tool("GDOF_EXAMPLE_SCENE")
    d = tmp_path_factory.mktemp("scene")
    flat, deep = d / "scene.exr", d / "deep.exr"
    subprocess.run([make, "--size", "160x90", "-o", str(flat), "--deep", str(deep)], check=True, capture_output=True)
    return flat, deep


def same_bits(a, b):
    """Arrays equal bit for bit (NaNs included)."""
    import numpy as np

    a, b = np.asarray(a), np.asarray(b)
    return a.shape == b.shape and a.dtype == b.dtype and np.array_equal(a.view(np.uint8), b.view(np.uint8))


def images_equal(path_a, path_b):
    """Two image files with the same parts, channels, windows and pixel bits."""
    a, b = gdof.read_image(str(path_a)), gdof.read_image(str(path_b))
    assert len(a) == len(b)
    for pa, pb in zip(a, b):
        assert pa.channels == pb.channels
        assert pa.data_window == pb.data_window and pa.display_window == pb.display_window
        if isinstance(pa, gdof.DeepImage):
            assert same_bits(pa.sample_counts, pb.sample_counts)
            for c in pa.channel_names:
                assert same_bits(pa.samples(c), pb.samples(c)), c
        else:
            for c in pa.channel_names:
                assert same_bits(pa.channel(c), pb.channel(c)), c
    return True

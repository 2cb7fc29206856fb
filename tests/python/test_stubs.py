"""The committed type stubs are those nanobind's stub generator writes for the
built module (regenerate: docs/python.md, "Type stubs")."""

import subprocess
import sys
from pathlib import Path

import pytest
from conftest import SOURCE

import gdof


def test_stub_matches_the_module(tmp_path):
    pytest.importorskip("nanobind.stubgen", reason="nanobind is not installed (tests/python/requirements.txt)")
    out = tmp_path / "_gdof.pyi"
    subprocess.run([sys.executable, "-m", "nanobind.stubgen", "-q", "-m", "gdof._gdof", "-p",
                    str(SOURCE / "python/stubgen_patterns.txt"), "-o", str(out)], check=True)
    committed = SOURCE / "python/gdof/_gdof.pyi"
    assert out.read_text() == committed.read_text(), (
        "python/gdof/_gdof.pyi is stale: regenerate it (docs/python.md, 'Type stubs')")
    # And the package next to the module ships it.
    assert (Path(gdof.__file__).parent / "py.typed").exists()

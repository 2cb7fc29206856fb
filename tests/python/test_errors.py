"""Errors raised in C++ arrive as gdof.Error with the library's message: the
text the CLI prints after its flag and file."""

import json

import pytest
from conftest import run_cli

import gdof


def cli_error(cli, *args):
    r = run_cli(cli, *args, check=False)
    assert r.returncode == 1, r.stderr
    lines = [l for l in r.stderr.splitlines() if l.startswith("gdof: error: ")]
    assert len(lines) == 1, r.stderr
    return lines[0][len("gdof: error: "):]


def test_blur_field_error_is_the_cli_message(cli, scene, tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"blurfield": {"kind": "focal_planes", "depths": [2.0], "max_blur": -3}}))
    printed = cli_error(cli, scene[0], "--blurfield", bad, "--diffuse", "-o", tmp_path / "x.exr")
    with pytest.raises(gdof.Error) as e:
        gdof.BlurField.read(str(bad))
    assert printed == "--blurfield " + str(e.value)
    assert "max_blur" in str(e.value) and e.value.code == "invalid_argument"
    assert not (tmp_path / "x.exr").exists()


def test_defocus_error_is_the_cli_message(cli, tmp_path):
    # A plate without depth: defocus() itself refuses it.
    path = tmp_path / "nodepth.exr"
    gdof.write_image(str(path), gdof.Image(["R", "G", "B", "A"], (0, 0, 32, 16)))
    lens = {"focal_length_mm": 50, "f_number": 2, "focus_distance": 3}
    flags = [a for k, v in lens.items() for a in ("--" + k.replace("_", "-"), v)]
    printed = cli_error(cli, path, *flags, "--diffuse", "-o", tmp_path / "x.exr")
    with pytest.raises(gdof.Error) as e:
        gdof.defocus(gdof.read_image(str(path)), **lens)
    # The CLI puts its flag and file in front, and the flag of the
    # setting at fault (the error's subject) after.
    flag = f" (--{e.value.subject.replace('_', '-')})" if e.value.subject else ""
    assert printed == f"--diffuse: '{path}': {e.value}{flag}"
    assert "depth" in str(e.value)

    # No lens at all: the camera's error, with its subject.
    printed = cli_error(cli, path, "--diffuse", "-o", tmp_path / "x.exr")
    with pytest.raises(gdof.Error) as e:
        gdof.defocus(gdof.read_image(str(path)))
    assert e.value.subject == "focal_length_mm"
    assert printed == f"--diffuse: '{path}': {e.value} (--focal-length-mm)"


def test_missing_file(tmp_path):
    with pytest.raises(gdof.Error) as e:
        gdof.read_image(str(tmp_path / "none.exr"))
    assert "none.exr" in str(e.value)


def test_a_missing_openimageio_module_is_the_cli_message(cli, tmp_path):
    # The module loads once per process, so each side runs in its own.
    import os
    import subprocess
    import sys
    png = tmp_path / "in.png"
    gdof.write_image(str(png), gdof.Image(["R", "G", "B"], (0, 0, 8, 4)))
    env = dict(os.environ, GDOF_OIIO_MODULE=str(tmp_path / "nowhere.so"))
    printed = subprocess.run([cli, str(png), "-o", str(tmp_path / "x.exr")], env=env, capture_output=True, text=True)
    assert printed.returncode == 1
    code = "import gdof\ntry:\n    gdof.read_image(%r)\nexcept gdof.Error as e:\n    print(e.code, e)\n" % str(png)
    raised = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    assert raised.returncode == 0, raised.stderr
    code_name, message = raised.stdout.strip().split(" ", 1)
    assert printed.stderr.strip().endswith(message), (printed.stderr, message)
    assert "gdof_oiio.so" in message and "nowhere.so' (GDOF_OIIO_MODULE): not found" in message
    assert not (tmp_path / "x.exr").exists()
    # EXR needs no module.
    exr = subprocess.run([sys.executable, "-c", "import gdof; gdof.write_image(%r, gdof.Image(['R'], (0, 0, 2, 2)))"
                          % str(tmp_path / "y.exr")], env=env, capture_output=True, text=True)
    assert exr.returncode == 0, exr.stderr

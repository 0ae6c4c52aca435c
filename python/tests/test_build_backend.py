"""`pip install ./python` on a fresh clone (issue 25 item 7): the build backend installs MuJoCo by
running scripts/setup.d/20-mujoco.sh when its library is missing, and when that fails stops with one
line naming the script instead of a Rust build-script panic. Checked on stand-in scripts in a
temporary tree (the real script downloads a wheel)."""

from __future__ import annotations

import importlib
import pathlib
import pytest

BACKEND = pathlib.Path(__file__).resolve().parents[1] / "build_backend"


@pytest.fixture
def backend(monkeypatch, tmp_path):
    monkeypatch.syspath_prepend(str(BACKEND))
    mod = importlib.import_module("dbot_build")
    script = tmp_path / "scripts" / "setup.d" / "20-mujoco.sh"
    script.parent.mkdir(parents=True)
    lib = tmp_path / ".mujoco" / "lib" / "libmujoco.so.3.17.0"
    monkeypatch.setattr(mod, "ROOT", tmp_path)
    monkeypatch.setattr(mod, "SCRIPT", script)
    monkeypatch.setattr(mod, "LIBRARY", lib)
    return mod, script, lib


def test_a_missing_library_is_installed_by_the_setup_script(backend) -> None:
    mod, script, lib = backend
    script.write_text(f"mkdir -p '{lib.parent}' && touch '{lib}'\n")
    mod._ensure_mujoco()
    assert lib.is_file()


def test_a_failed_install_stops_with_one_line_naming_the_script(backend) -> None:
    mod, script, _ = backend
    script.write_text("echo 'pip: no network' >&2; exit 1\n")
    with pytest.raises(SystemExit) as stop:
        mod._ensure_mujoco()
    text = str(stop.value)
    assert "\n" not in text
    assert "scripts/setup.d/20-mujoco.sh" in text
    assert "pip: no network" in text


def test_an_installed_library_runs_nothing(backend) -> None:
    mod, script, lib = backend
    lib.parent.mkdir(parents=True)
    lib.touch()
    script.write_text("exit 1\n")  # would fail if it ran
    mod._ensure_mujoco()

"""`pip install ./python` on a fresh clone (issue 25 item 7): the build backend installs MuJoCo by
running scripts/setup.d/20-mujoco.sh when its library is missing, and when that fails stops with one
line naming the script instead of a Rust build-script panic. Checked on stand-in scripts in a
temporary tree (the real script downloads a wheel)."""

from __future__ import annotations

import importlib
import pathlib
import pytest
from conftest import need_module

BACKEND = pathlib.Path(__file__).resolve().parents[1] / "build_backend"


@pytest.fixture
def backend(monkeypatch, tmp_path):
    need_module("maturin")  # the backend wraps maturin's hooks
    monkeypatch.syspath_prepend(str(BACKEND))
    mod = importlib.import_module("dbot_build")
    script = tmp_path / "scripts" / "setup.d" / "20-mujoco.sh"
    script.parent.mkdir(parents=True)
    lib = tmp_path / ".mujoco" / "lib" / "libmujoco.so.3.17.0"
    monkeypatch.setattr(mod, "ROOT", tmp_path)
    monkeypatch.setattr(mod, "SCRIPT", script)
    monkeypatch.setattr(mod, "LIBRARY", lib)
    return mod, script, lib


def one_line_stop(mod) -> str:
    """What ``_ensure_mujoco`` stops the build with, asserted to be one line."""
    with pytest.raises(SystemExit) as stop:
        mod._ensure_mujoco()
    text = str(stop.value)
    assert "\n" not in text
    return text


def test_a_missing_library_is_installed_by_the_setup_script(backend) -> None:
    mod, script, lib = backend
    script.write_text(f"mkdir -p '{lib.parent}' && touch '{lib}'\n")
    mod._ensure_mujoco()
    assert lib.is_file()


@pytest.mark.parametrize(
    ("script_text", "said"),
    [
        # A failed install: the script's own words and its name.
        (
            "echo 'pip: no network' >&2; exit 1\n",
            ["scripts/setup.d/20-mujoco.sh", "pip: no network"],
        ),
        # The script succeeds, but the library is still missing.
        (
            "exit 0\n",
            ["scripts/setup.d/20-mujoco.sh", "ended without .mujoco/lib/libmujoco.so.3.17.0"],
        ),
        # A silent failure still names the script.
        ("exit 3\n", ["(no output)", "run `bash scripts/setup.d/20-mujoco.sh`"]),
    ],
    ids=["failed_install", "script_installs_nothing", "silent_failure"],
)
def test_a_setup_script_without_the_library_stops_with_one_line_naming_it(
    backend, script_text: str, said: list[str]
) -> None:
    mod, script, _ = backend
    script.write_text(script_text)
    text = one_line_stop(mod)
    for words in said:
        assert words in text


def test_an_installed_library_runs_nothing(backend) -> None:
    mod, script, lib = backend
    lib.parent.mkdir(parents=True)
    lib.touch()
    script.write_text("exit 1\n")  # would fail if it ran
    mod._ensure_mujoco()


def test_an_own_mujoco_folder_without_the_library_stops_with_one_line(
    backend, monkeypatch, tmp_path
) -> None:
    mod, script, lib = backend
    empty = tmp_path / "empty"
    empty.mkdir()
    monkeypatch.setenv("MUJOCO_DYNAMIC_LINK_DIR", str(empty))
    script.write_text(f"touch '{tmp_path / 'ran'}'\n")
    text = one_line_stop(mod)
    assert f"MUJOCO_DYNAMIC_LINK_DIR={empty} has no libmujoco.so.3.17.0" in text
    assert "scripts/setup.d/20-mujoco.sh" in text
    assert not (tmp_path / "ran").exists()  # the script installs elsewhere: not run


def test_an_own_mujoco_folder_with_the_library_runs_nothing(backend, monkeypatch, tmp_path) -> None:
    mod, script, _ = backend
    own = tmp_path / "own"
    own.mkdir()
    (own / "libmujoco.so.3.17.0").touch()
    monkeypatch.setenv("MUJOCO_DYNAMIC_LINK_DIR", str(own))
    script.write_text("exit 1\n")  # would fail if it ran
    mod._ensure_mujoco()


def test_the_backend_looks_where_cargo_and_the_script_put_the_library() -> None:
    """The backend's paths against the two files that fix them: .cargo/config.toml (the folder the
    Rust build links) and scripts/setup.d/20-mujoco.sh (the folder it fills)."""
    import sys
    import tomllib

    sys.path.insert(0, str(BACKEND))
    try:
        mod = importlib.import_module("dbot_build")
    finally:
        sys.path.remove(str(BACKEND))
    root = BACKEND.parents[1]
    config = tomllib.loads((root / ".cargo" / "config.toml").read_text())
    linked = config["env"]["MUJOCO_DYNAMIC_LINK_DIR"]
    assert linked["relative"] is True
    assert mod.LIBRARY.parent == root / linked["value"]
    script = (root / "scripts" / "setup.d" / "20-mujoco.sh").read_text()
    assert 'lib="$dir/lib-from-scripts-setup.d-20-mujoco.sh"' in script
    assert "dir=.mujoco" in script
    assert "version=3.17.0" in script and mod.LIBRARY.name == "libmujoco.so.3.17.0"
    assert mod.SCRIPT.is_file()

"""The type stubs of the native module (python/dbot/_native.pyi, what editors and type checkers
see) against the compiled module itself, by mypy's stubtest (an external checker): every
function, class, method and parameter the module has is in the stubs with the same name, kind
and default, and the stubs declare nothing the module lacks but the names of
stubtest-allowlist.txt, each with its reason (an entry no longer needed fails too). And the
package's own Python (python/dbot) type-checks against those stubs with mypy: what the package
passes to and expects from the module is what the stubs promise a user's code."""

from __future__ import annotations

import os
import pathlib
import shutil
import subprocess
import sys

HERE = pathlib.Path(__file__).resolve().parent


def test_the_native_stubs_match_the_module(tmp_path) -> None:
    # The stubs alone, under an empty package stub: stubtest type-checks what it is given, and
    # the package's own Python modules are not what this test checks.
    (tmp_path / "dbot").mkdir()
    (tmp_path / "dbot" / "__init__.pyi").write_text("")
    shutil.copy(HERE.parent / "dbot" / "_native.pyi", tmp_path / "dbot" / "_native.pyi")
    run = subprocess.run(
        [
            sys.executable,
            "-m",
            "mypy.stubtest",
            "dbot._native",
            "--allowlist",
            str(HERE / "stubtest-allowlist.txt"),
        ],
        capture_output=True,
        text=True,
        timeout=600,
        cwd=tmp_path,
        env={**os.environ, "MYPYPATH": str(tmp_path)},
    )
    assert run.returncode == 0, run.stdout + run.stderr


def test_the_package_type_checks_against_its_stubs(tmp_path) -> None:
    run = subprocess.run(
        [
            sys.executable,
            "-m",
            "mypy",
            "--cache-dir",
            str(tmp_path / "cache"),
            str(HERE.parent / "dbot"),
        ],
        capture_output=True,
        text=True,
        timeout=600,
        cwd=tmp_path,
    )
    assert run.returncode == 0, run.stdout + run.stderr

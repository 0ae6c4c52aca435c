"""`dbot.doctor()` against `dbot sim-bus` on a pseudo-terminal: the same items in the same words
as `dbot doctor` (the CLI binary) on the same bus, a healthy chain passing and a chain missing its
servo 22 failing (the CLI exits non-zero)."""

from __future__ import annotations

import pathlib
import subprocess
import time

import pytest

import dbot
from dbot_cli import dbot_cli


def serve(tmp_path: pathlib.Path, servos: int):
    path = tmp_path / f"bus{servos}"
    server = subprocess.Popen(
        [str(dbot_cli()), "sim-bus", "--servos", str(servos), "--baud", "1000000",
         "--return-delay-us", "0", "--quiet", "--link", str(path)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    deadline = time.monotonic() + 30
    while not path.exists():
        assert server.poll() is None, "dbot sim-bus stopped"
        assert time.monotonic() < deadline, "dbot sim-bus did not link its pty"
        time.sleep(0.05)
    return server, str(path)


@pytest.fixture()
def bus(tmp_path: pathlib.Path, request):
    server, path = serve(tmp_path, request.param)
    try:
        yield path
    finally:
        server.terminate()
        server.wait(timeout=30)


def cli_doctor(path: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [str(dbot_cli()), "doctor", "--bus", path, "--baud", "1000000"],
        capture_output=True, text=True, timeout=600,
    )


@pytest.mark.parametrize("bus", [22], indirect=True)
def test_a_healthy_chain_passes_in_the_cli_words(bus: str) -> None:
    report = dbot.doctor(bus=bus, baud=1_000_000, quiet=True)
    assert report["ok"], report["text"]
    # The servo bus, 22 servos, the supply.
    assert len(report["items"]) == 24
    assert {i["outcome"] for i in report["items"]} == {"pass"}
    cli = cli_doctor(bus)
    assert cli.returncode == 0, cli.stderr
    assert cli.stdout == report["text"]


@pytest.mark.parametrize("bus", [21], indirect=True)
def test_a_missing_servo_fails_in_the_cli_words(bus: str) -> None:
    report = dbot.doctor(bus=bus, baud=1_000_000, quiet=True)
    assert not report["ok"]
    failed = [i for i in report["items"] if i["outcome"] == "fail"]
    assert [i["name"] for i in failed] == [n for n in (i["name"] for i in report["items"]) if n.startswith("servo ID 22 ")]
    assert failed[0]["detail"].startswith("missing")
    cli = cli_doctor(bus)
    assert cli.returncode != 0
    assert cli.stdout == report["text"]
    assert "the robot is not ready" in cli.stderr


def test_the_emulated_board_and_its_servos_are_checked_through_it(emulator_port: str) -> None:
    """The doctor on the emulated board (the release firmware image in the RP2040 emulator, over
    its USB pseudo-terminal): the board is found with this host's protocol and table versions and
    its bus settings, and every servo of the model file is read through the board (`ReadServo`,
    protocol version 9) on the emulator's virtual servo chain: each answers with the e-manual's
    model number for its model file entry, and the supply reads the virtual servos' 12.0 V. The
    CLI prints the same lines."""
    report = dbot.doctor(port=emulator_port, quiet=True)
    items = {i["name"]: i for i in report["items"]}
    assert items["board"]["outcome"] == "pass", report["text"]
    assert items["board bus"]["outcome"] == "pass", report["text"]
    servos = [i for n, i in items.items() if n.startswith("servo ID ")]
    assert len(servos) == 22, report["text"]
    for i in servos:
        want = "model number 311" if "MX-64" in i["name"] else "model number 30)"
        assert want in i["detail"], i
    assert "12.0 V" in items["supply voltage"]["detail"], report["text"]
    cli = subprocess.run(
        [str(dbot_cli()), "doctor", "--port", emulator_port],
        capture_output=True, text=True, timeout=600,
    )
    assert cli.stdout == report["text"], cli.stderr

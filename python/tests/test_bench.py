"""`dbot.Bench` against `dbot sim-bus` on a pseudo-terminal: scan, read and write give what
`dbot dxl` (the CLI binary) prints on the same bus, and bad input names the field."""

from __future__ import annotations

import pathlib
import re
import subprocess
import time

import pytest

import dbot
from dbot_cli import dbot_cli

SLACK_US = 300_000


@pytest.fixture()
def link(tmp_path: pathlib.Path):
    path = tmp_path / "bus"
    server = subprocess.Popen(
        [str(dbot_cli()), "sim-bus", "--servos", "3", "--baud", "1000000", "--quiet", "--link", str(path)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    try:
        deadline = time.monotonic() + 30
        while not path.exists():
            assert server.poll() is None, "dbot sim-bus stopped"
            assert time.monotonic() < deadline, "dbot sim-bus did not link its pty"
            time.sleep(0.05)
        yield str(path)
    finally:
        server.terminate()
        server.wait(timeout=30)


def dxl(link: str, *args: str) -> str:
    out = subprocess.run(
        [str(dbot_cli()), "dxl", *args, "--port", link, "--baud", "1000000",
         "--reply-slack-us", str(SLACK_US)],
        capture_output=True, text=True, timeout=120,
    )
    assert out.returncode == 0, out.stdout + out.stderr
    return out.stdout


def test_scan_read_write_match_the_cli(link: str) -> None:
    bench = dbot.Bench.open(link, baud=1000000, reply_slack_us=SLACK_US)
    found = bench.scan(max_id=4)
    # The port is opened exclusively: closed, the CLI can open it (and the bench no longer has a rate).
    bench.close()
    assert bench.baud is None
    # The CLI's lines, parsed: "ID   1: model 30 (MX-28(2.0)), firmware 52".
    cli = [
        (int(m[1]), int(m[2]), int(m[3]))
        for m in re.finditer(r"ID +(\d+): model (\d+) \([^)]*\)\)?, firmware (\d+)", dxl(link, "scan", "--max-id", "4"))
    ]
    assert [(f["id"], f["model_number"], f["firmware"]) for f in found] == cli
    # sim-bus puts the robot's servos at IDs 1..=3; the e-manual's model numbers are 30 (MX-28(2.0))
    # and 311 (MX-64(2.0)).
    assert [f["id"] for f in found] == [1, 2, 3]
    assert all(f["model_number"] in (30, 311) for f in found)
    assert all(f["baud"] == 1000000 for f in found)

    with dbot.Bench.open(link, baud=1000000, reply_slack_us=SLACK_US) as bench:
        bench.write(2, 1234, field="Goal Position")
        r = bench.read(2, field="goal_position")
        assert (r["value"], r["addr"], r["length"]) == (1234, 116, 4)
    assert "= 1234 " in dxl(link, "read", "--id", "2", "--field", "Goal Position")
    # Written by the CLI, read by Python.
    dxl(link, "write", "--id", "2", "--field", "Homing Offset", "--value", "-5")
    r = dbot.Bench.open(link, baud=1000000, reply_slack_us=SLACK_US).read(2, addr=20, length=4)
    assert (r["signed"], r["value"]) == (-5, 2**32 - 5)


def test_bad_field_and_value_name_the_problem(link: str) -> None:
    bench = dbot.Bench.open(link, baud="1000000", reply_slack_us=SLACK_US)
    with pytest.raises(ValueError, match='field "Goal Positon": no such control table field'):
        bench.read(2, field="Goal Positon")
    with pytest.raises(ValueError, match=r"value for LED: 300 does not fit in 1 byte\(s\)"):
        bench.write(2, 300, field="LED")
    with pytest.raises(ValueError, match="`fast` is not a rate"):
        dbot.Bench.open(link, baud="fast")
    with pytest.raises(dbot.BoardError, match="ID 9"):
        bench.read(9, field="LED")


def test_a_port_that_is_no_serial_port_is_refused_with_the_clis_words(tmp_path: pathlib.Path) -> None:
    # /dev/null is a character device but no terminal; a regular file and a missing path are
    # named as what they are, before the terminal layer's "Not a typewriter".
    notes = tmp_path / "notes.txt"
    notes.write_text("x")
    for port, words in [
        ("/dev/null", "/dev/null is a device but not a serial port (not a terminal)"),
        (str(notes), f"{notes} is a regular file, not a serial port"),
        (str(tmp_path / "ttyUSB9"), f"{tmp_path / 'ttyUSB9'}: no such serial port"),
    ]:
        with pytest.raises(ValueError, match=re.escape(words)):
            dbot.Bench.open(port, baud=1000000).scan(max_id=1)
        out = subprocess.run(
            [str(dbot_cli()), "dxl", "scan", "--port", port, "--baud", "1000000"],
            capture_output=True, text=True, timeout=60,
        )
        assert out.returncode == 1 and words in out.stderr, out.stderr

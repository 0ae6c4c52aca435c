"""Drives `dbot sim-bus` with the official ROBOTIS Dynamixel SDK (dynamixel-sdk, Protocol 2.0).

Usage: sdk_check.py PORT BAUD SERVOS MX64_IDS (comma-separated: the IDs the robot's model file puts
an MX-64(2.0) at, passed by host/dbot/tests/integration/dxl_sdk.rs from drosophibot2.toml). Exits non-zero with a message naming the first check that
failed. Expected values come from the e-manual (model numbers MX-28(2.0) = 30, MX-64(2.0) = 311,
addresses) and from what this script itself wrote.
"""

import sys
import time

import dynamixel_sdk.port_handler
from dynamixel_sdk import (COMM_RX_TIMEOUT, COMM_SUCCESS, GroupSyncRead, GroupSyncWrite,
                           PacketHandler, PortHandler)

# The SDK's reply timeouts are 2 x LATENCY_TIMER (16 ms, for FTDI adapters) + wire time + 2 ms.
# A pseudo-terminal has no latency timer, but a busy CI machine can deschedule the server for
# longer than 34 ms: give it 2 x 100 ms. Wire timing is tested in Rust on simulated time.
dynamixel_sdk.port_handler.LATENCY_TIMER = 100

ADDR_MODEL, ADDR_TORQUE, ADDR_GOAL, ADDR_FEEDBACK, ADDR_POSITION = 0, 64, 116, 126, 132


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def main():
    port_name, baud, servos = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    mx64_ids = {int(i) for i in sys.argv[4].split(",")}
    ids = list(range(1, servos + 1))
    port = PortHandler(port_name)
    ph = PacketHandler(2.0)
    if not port.openPort() or not port.setBaudRate(baud):
        fail("cannot open %s at %d" % (port_name, baud))

    for i in ids:
        model, comm, err = ph.ping(port, i)
        want = 311 if i in mx64_ids else 30
        if comm != COMM_SUCCESS or err != 0 or model != want:
            fail("ping ID %d: %s, error %d, model %d (want %d)" % (i, ph.getTxRxResult(comm), err, model, want))
    print("ok: ping of %d IDs" % len(ids))

    found = ph.broadcastPing(port)
    if found[1] != COMM_SUCCESS or sorted(found[0].keys()) != ids:
        fail("broadcast ping: %s, IDs %s" % (ph.getTxRxResult(found[1]), sorted(found[0].keys())))
    print("ok: broadcast ping")

    for i in ids:
        model, comm, err = ph.read2ByteTxRx(port, i, ADDR_MODEL)
        want = 311 if i in mx64_ids else 30
        if comm != COMM_SUCCESS or model != want:
            fail("read Model Number of ID %d: %s, %d (want %d)" % (i, ph.getTxRxResult(comm), model, want))
    print("ok: model numbers")

    _, comm, _ = ph.ping(port, 40)
    if comm != COMM_RX_TIMEOUT:
        fail("ping of absent ID 40 should time out, got %s" % ph.getTxRxResult(comm))

    for i in ids:
        comm, err = ph.write1ByteTxRx(port, i, ADDR_TORQUE, 1)
        if comm != COMM_SUCCESS or err != 0:
            fail("torque on ID %d: %s, error %d" % (i, ph.getTxRxResult(comm), err))
    for i in ids:
        goal = 1900 + 10 * i
        comm, err = ph.write4ByteTxRx(port, i, ADDR_GOAL, goal)
        back, comm2, _ = ph.read4ByteTxRx(port, i, ADDR_GOAL)
        if comm != COMM_SUCCESS or err != 0 or comm2 != COMM_SUCCESS or back != goal:
            fail("write goal %d to ID %d read back %d (write: %s, error %d; read: %s)"
                 % (goal, i, back, ph.getTxRxResult(comm), err, ph.getTxRxResult(comm2)))
    comm, err = ph.write4ByteTxRx(port, 1, ADDR_GOAL, 5000)
    if comm != COMM_SUCCESS or err & 0x7F != 6:
        fail("goal beyond Max Position Limit should be a Data Limit error (6), got %s, error %d" % (ph.getTxRxResult(comm), err))
    print("ok: write goals")

    sw = GroupSyncWrite(port, ph, ADDR_GOAL, 4)
    goals = {i: 2200 - 7 * i for i in ids}
    for i, g in goals.items():
        sw.addParam(i, list(g.to_bytes(4, "little")))
    comm = sw.txPacket()
    if comm != COMM_SUCCESS:
        fail("sync write: %s" % ph.getTxRxResult(comm))
    print("ok: sync write")

    # Moves are at most ~300 ticks (0.46 rad) at ~5.8 rad/s: well settled after 1 s.
    time.sleep(1.0)
    sr = GroupSyncRead(port, ph, ADDR_FEEDBACK, 10)
    for i in ids:
        sr.addParam(i)
    comm = sr.txRxPacket()
    if comm != COMM_SUCCESS:
        fail("sync read: %s" % ph.getTxRxResult(comm))
    for i in ids:
        if not sr.isAvailable(i, ADDR_POSITION, 4):
            fail("sync read: no position for ID %d" % i)
        pos = sr.getData(i, ADDR_POSITION, 4)
        if abs(pos - goals[i]) > 2:
            fail("ID %d at %d after sync write of goal %d" % (i, pos, goals[i]))
    print("ok: sync read of %d servos at their sync-written goals" % len(ids))
    port.closePort()
    print("PASS")


if __name__ == "__main__":
    main()

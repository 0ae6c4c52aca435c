"""The environment's descending action mode: :class:`DescendingEnv`, (heading, speed) in.

A high-level controller (a steering model of the fly's descending neurons, say) drives the robot
the way the lab's newer stack does, with one heading in rad from straight forward and a speed,
instead of 22 joint targets. The board does the rest on its own: it plays the stored steering
family (three gaits in slots 0, 1, 2: straight, turning left by ``range_rad`` of yaw per stance,
turning right by as much; the same slices, period and leg phases) and blends them at the heading's
share, the weight and the speed changing only at step boundaries (``protocol::steer``,
``Board.steer``). No host plans in the loop, so the same controller runs on the physics robot and
on a board port (the RP2040 emulator's pseudo-terminal, a real board) unchanged.

``reset`` leaves the robot standing (torque on, nothing played) with the family uploaded and set,
as :class:`dbot.env.DbotEnv` leaves it standing before streaming; the first ``step`` starts the
steered walk (the board ramps to the blend's first slice, then walks). ``step(action)`` sends
``Board.steer(heading, speed)`` when the action changed and lets ``cycles_per_step`` bus cycles
pass (default 10, 0.1 s), counted on the board's telemetry (one record per bus cycle), never on
the host's clock. A heading or speed given mid-swing takes over at the next step boundary.

Action: a ``Box`` of (heading rad, speed), heading in ``-range_rad ..= range_rad`` (the family's
range, positive left: REP-103 yaw), speed in ``0.1 ..= 1.0`` of the planned speed. The firmware
takes 0.1 to 10 (a period scale of 1 / speed at step boundaries), but faster than planned the
servos may not follow: ``Board.steer`` checks the family's tables at that speed against the
servos (``board::rules::steer``, as ``Board.play`` checks a shorter period) and refuses a speed
they cannot follow, so this environment stops at the plan's own speed, where the family was built
feasible (slower is at least as feasible).

Observation and ``info``: the keys and spaces of :class:`~dbot.env.DbotEnv`. The angles, velocities
and loads are the board's telemetry of the step's last bus cycle; ``setpoint_age`` is always 0
here (no setpoints stream: the board plays its tables). ``info`` adds ``step`` and ``slice`` (the
playback position the board reports; 0, 0 while standing or ramping) to DbotEnv's ``time_s``,
``state`` (the board's state now: ``Standing``, ``Ramping``, ``Walking``, ``Fault`` ...) and, on
the physics robot, ``body``. Termination, truncation and the default reward are DbotEnv's (a
fault, a fall; ``max_episode_steps``; forward progress). Every wait is bounded in bus cycles of
the board (and on a port by ``reply_timeout_s`` of wall time per record) and raises naming what it
waited for.
"""

from __future__ import annotations

import math
import time
from typing import TYPE_CHECKING, Any, Mapping

import numpy as np
from gymnasium import spaces

from ._native import Board, Model, plan
from .env import STRAIN_AGE_BOUND_S, DbotEnv

if TYPE_CHECKING:  # the records' TypedDicts exist only in the stubs
    from ._native import Status, Telemetry

#: The family's default turn, rad of yaw per stance: about the largest whose first slice the
#: board's switch rule admits beside the straight gait's at 20 slices (python/tests/test_steer.py:
#: 0.1 rad is refused).
RANGE_RAD = 0.06
#: Speeds the action may ask for, 1 = as planned (module text: why not above 1).
SPEED_MIN, SPEED_MAX = 0.1, 1.0
#: Slots of the family: straight, left, right.
FAMILY_SLOTS = (0, 1, 2)
#: Bus cycles a stop may take, the bound of waiting for standing: the rest of a whole step at the
#: slowest speed (2.5 s / 0.1 = 2500 cycles at 100 Hz), with room for a ramp (measured on the
#: physics robot: 2150 cycles from a stop at speed 0.1 to standing).
STOP_CYCLES = 4000


class DescendingEnv(DbotEnv):
    """Drosophibot II walking under a descending command: (heading, speed) in, what the board
    reports out."""

    def __init__(
        self,
        port: str = "physics",
        *,
        model: Model | None = None,
        range_rad: float = RANGE_RAD,
        slices: int = 20,
        cycles_per_step: int = 10,
        **options: Any,
    ) -> None:
        """``options``: DbotEnv's keyword arguments with DbotEnv's defaults
        (``max_episode_steps``, ``stiffness_nm_rad``, ``settle_s``, ``reply_timeout_s``,
        ``fall_height_fraction``, ``fall_tilt_rad``, ``reward``, ``render_mode``); not ``gait``
        (the family's straight gait is the plan), ``torques`` or ``timeout_cycles`` (no
        setpoints stream here)."""
        for name in ("gait", "torques", "timeout_cycles"):
            if name in options:
                raise TypeError(
                    f"DescendingEnv takes no {name}=: the board plays the steering family, "
                    "nothing streams"
                )
        if not (range_rad > 0.0 and math.isfinite(range_rad)):
            raise ValueError(f"range_rad = {range_rad}: give a positive turn per stance, rad")
        model = model if model is not None else Model.builtin("drosophibot2")
        family = [plan(model, slices=slices, rotation_rad=r) for r in (0.0, range_rad, -range_rad)]
        super().__init__(
            port, model=model, gait=family[0], cycles_per_step=cycles_per_step, **options
        )
        self.range_rad = float(range_rad)
        self._tables = [p.step_table() for p in family]
        self._commands = spaces.Box(
            np.array([-self.range_rad, SPEED_MIN]),
            np.array([self.range_rad, SPEED_MAX]),
            dtype=np.float64,
        )
        self.action_space = self._commands
        self._command: tuple[float, float] | None = None
        self._cycle = 0

    # -- reset -------------------------------------------------------------------------------

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        """The robot standing (torque on, nothing played) with the steering family in slots 0,
        1, 2 and set. Options as DbotEnv's: ``scene`` (physics robot only), ``stiffness_nm_rad``."""
        # gymnasium.Env.reset seeds self.np_random; DbotEnv.reset would enter streaming.
        super(DbotEnv, self).reset(seed=seed)
        uploads = list(zip(FAMILY_SLOTS, self._tables, strict=True))
        board = self._prepare_board(options, uploads)
        board.set_steer_family(*FAMILY_SLOTS, self.range_rad)
        board.set_telemetry(1)
        self._command = None
        self._steps = 0
        # The records kept while settling are old: the observation is the next cycle's.
        self._cycle = board.status()["counters"]["cycles"]
        obs, rec = self._advance(1)
        self.rest_rad = np.asarray(rec["commanded_rad"][0], dtype=np.float64)
        return self._begin_episode(obs, self._info_of(rec))

    def _wait_stopped(self, board: Board) -> None:
        """The walk stopped within STOP_CYCLES of the board's own bus cycles, or an error."""
        self._wait_state(board, ("Standing", "Idle"), STOP_CYCLES, "the walk to stop")

    def _wait_state(
        self, board: Board, states: tuple[str, ...], cycles: int, what: str
    ) -> Status:
        """Polls the status until the board is in one of `states`, for at most `cycles` of its
        own bus cycles; returns that status. A board whose cycle counter stands still for
        `reply_timeout_s` of wall time (a wedged emulator, a lost link) ends the wait too: the
        wall clock only detects a stall, the bound is the board's."""
        st = board.status()
        start = last = st["counters"]["cycles"]
        moved = time.monotonic()
        while st["state"] not in states:
            n = st["counters"]["cycles"]
            if n - start > cycles:
                why = f"{cycles} bus cycles passed"
                break
            if n != last:
                last, moved = n, time.monotonic()
            elif time.monotonic() - moved > self.reply_timeout_s:
                why = f"the board counted no bus cycle for {self.reply_timeout_s} s"
                break
            board.wait(0.01)
            st = board.status()
        else:
            return st
        raise RuntimeError(
            f"{self.port}: waited for {what} (state {' or '.join(states)}): {why}; the board is "
            f"{st['state']}"
        )

    # -- step --------------------------------------------------------------------------------

    def step(
        self, action: np.ndarray
    ) -> tuple[dict[str, np.ndarray], float, bool, bool, dict[str, Any]]:
        if self.board is None:
            raise RuntimeError("call reset() before step()")
        a = np.asarray(action, dtype=np.float64)
        if a.shape != (2,):
            raise ValueError(f"action of shape {a.shape}: give (heading rad, speed)")
        a = np.clip(a, self._commands.low, self._commands.high)
        command = (float(a[0]), float(a[1]))
        before = self._info
        state = before.get("state")
        if command != self._command and state in ("Idle", "Standing", "Ramping", "Walking"):
            self.board.steer(*command)
            self._command = command
        obs, rec = self._advance(self.cycles_per_step)
        info = self._info_of(rec)
        self._info = info
        self._steps += 1
        if self.render_mode is not None:
            self._poses.append(self._pose(obs))
        terminated = info["state"] == "Fault" or self._fell(info)
        truncated = self._steps >= self.max_episode_steps
        reward = float(self.reward_fn(before, info, obs, a))
        return obs, reward, terminated, truncated, dict(info)

    def _advance(self, cycles: int) -> tuple[dict[str, np.ndarray], Telemetry]:
        """Lets `cycles` bus cycles pass, counted by their telemetry records (one per cycle:
        `set_telemetry(1)`), and returns the observation of the last one with its record.
        Records older than the last step's are skipped. A record that does not come within one
        cycle's wait on the physics robot (its clock moves only while waiting) or
        `reply_timeout_s` on a port raises, saying which cycle it waited for."""
        assert self.board is not None
        target = self._cycle + cycles
        timeout = 1.0 if self.physics else self.reply_timeout_s
        rec = None
        # At most `cycles` new records are needed; the budget allows for a backlog of old ones.
        for _ in range(cycles + 10_000):
            got = self.board.next_telemetry(timeout_s=timeout)
            if got is None:
                st = self.board.status()
                raise RuntimeError(
                    f"{self.port}: no telemetry for bus cycle {self._cycle + 1} of {target} "
                    f"within {timeout} s of board time (state {st['state']}, the board at "
                    f"cycle {st['counters']['cycles']})"
                )
            cycle = int(got["cycle"][0])
            if cycle <= self._cycle:
                continue
            rec = got
            self._cycle = cycle
            if cycle >= target:
                break
        else:
            raise RuntimeError(f"{self.port}: more than 10000 old telemetry records kept")
        assert rec is not None
        self.last_record = rec
        obs = self._joints_observed(rec, np.zeros(1, dtype=np.float64))
        if self.strain_names:
            obs.update(self._strain_now(float(rec["time_s"][0])))
        self._last_obs = obs
        return obs, rec

    def _strain_now(self, time_s: float) -> dict[str, np.ndarray]:
        """The physics robot's latest gauge sample and its age at the record's time `time_s`
        (telemetry carries no strain, so it is read from the body, as streaming does)."""
        assert self.board is not None
        got = self.board.strain()
        if got is None:
            raise RuntimeError(f"{self.port}: no strain sample after bus cycle {self._cycle}")
        age = min(max(time_s - float(got["time_s"]), 0.0), STRAIN_AGE_BOUND_S)
        return {
            "strain_microstrain": np.asarray(got["microstrain"], dtype=np.float64),
            "strain_age_s": np.array([age], dtype=np.float64),
        }

    def _info_of(self, rec: Mapping[str, Any]) -> dict[str, Any]:
        assert self.board is not None
        info: dict[str, Any] = {
            "time_s": float(rec["time_s"][0]),
            "state": self.board.status()["state"],
            "step": int(rec["step"][0]),
            "slice": int(rec["slice"][0]),
        }
        if self.physics:
            info["body"] = self.board.body()
        if self._predicted is not None:
            # The straight gait's prediction at the slice the board plays (a blend's own strain
            # is not planned).
            row = self._predicted[info["slice"] % len(self._predicted)]
            info["predicted_strain_microstrain"] = row.copy()
        return info

    def close(self) -> None:
        """Stops a steered walk on a board port (at the end of its step) and closes the link."""
        if self.board is not None and not self.physics:
            try:
                if self.board.status()["state"] in ("Walking", "Ramping", "Stopping"):
                    self.board.stop()
                    self._wait_state(self.board, ("Standing",), STOP_CYCLES, "the walk to stop")
                self.board.set_telemetry(0)
            finally:
                self.board.close()
                self.board = None
            return
        super().close()

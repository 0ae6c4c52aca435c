"""Python peers of the bench, on the inputs exported by `host/planner/examples/bench_export.rs`.

Solves the same per-slice inverse dynamics with SciPy SLSQP and Clarabel (full per-body system, as
the paper poses it) and with NumPy (reduced problem: foot forces only, torques from Pinocchio's
RNEA), runs Pinocchio's RNEA on one exported leg and a reference pseudo-inverse IK, and prints the
ratio table (peer time / our time) with the agreement of every answer.

Usage: python peers.py OUT_DIR [--slsqp-slices N] [--firmware FIRMWARE_LOG]
"""

import argparse
import json
import os
import re
import time

import clarabel
import numpy as np
import pinocchio as pin
import scipy
import scipy.sparse as sp
from scipy.optimize import minimize


def best_time(f, reps, rounds=5):
    """Median thread CPU seconds per call over `rounds` rounds of `reps` calls (after one warm-up
    call). Thread CPU time, as on our side, so that other load on a shared machine does not count."""
    out = f()
    ts = []
    for _ in range(rounds):
        t = time.thread_time()
        for _ in range(reps):
            f()
        ts.append((time.thread_time() - t) / reps)
    return float(np.median(ts)), out


# ---------------------------------------------------------------- full system (paper's form)
def full_problem(sl):
    f = sl["full"]
    tr = np.array(f["triplets"])
    a = sp.csc_matrix(
        (tr[:, 2], (tr[:, 0].astype(int), tr[:, 1].astype(int))), shape=(f["rows"], f["cols"])
    )
    b = np.array(f["rhs"])
    n = f["cols"]
    p = np.zeros((n, n))
    q = np.zeros(n)
    const = 0.0
    for c in f["cost"]:
        u = np.array(c["axis"])
        i = c["col"]
        p[i : i + 3, i : i + 3] += np.outer(u, u) / c["k"]
        q[i : i + 3] += -c["spring"] * u / c["k"]
        const += 0.5 * c["spring"] ** 2 / c["k"]
    return p, q, const, a, b


def solve_clarabel(p, q, a, b):
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    psp = sp.csc_matrix(np.triu(p))
    solver = clarabel.DefaultSolver(psp, q, a, b, [clarabel.ZeroConeT(a.shape[0])], settings)
    sol = solver.solve()
    return np.array(sol.x), str(sol.status)


def solve_slsqp(p, q, const, a, b):
    ad = a.toarray()
    # Start from the least-squares solution of the equations (feasible; independent of our answer)
    # and scale the objective by its cost there so that ftol is a relative tolerance.
    x0 = np.linalg.lstsq(ad, b, rcond=None)[0]
    f0 = max(abs(0.5 * x0 @ p @ x0 + q @ x0 + const), 1e-300)
    res = minimize(
        lambda x: (0.5 * x @ p @ x + q @ x + const) / f0,
        x0,
        jac=lambda x: (p @ x + q) / f0,
        method="SLSQP",
        constraints=[{"type": "eq", "fun": lambda x: ad @ x - b, "jac": lambda x: ad}],
        options={"ftol": 1e-12, "maxiter": 2000},
    )
    return res.x, res


def objective(p, q, const, x):
    return float(0.5 * x @ p @ x + q @ x + const)


# ---------------------------------------------------------------- reduced problem with Pinocchio
class Reduced:
    """Unknowns: stance-foot GRF. Torques tau = RNEA(q, v, a) - sum J_f^T G_f (Pinocchio, free
    flyer at the thorax); thorax equilibrium = the 6 base rows; cost sum (tau_a - spring_a)^2/2k."""

    def __init__(self, urdf, doc):
        self.model = pin.buildModelFromUrdf(urdf, pin.JointModelFreeFlyer())
        self.data = self.model.createData()
        self.joint_names = [j["name"] for j in doc["joints"]]
        # Our joint index -> Pinocchio v index for actuated joints.
        self.act = []
        for i, j in enumerate(doc["joints"]):
            if j["actuated"]:
                jid = self.model.getJointId(j["name"])
                self.act.append((i, self.model.idx_qs[jid], self.model.idx_vs[jid], j["k"]))
        self.frames = [self.model.getFrameId(f"{leg}_tip") for leg in doc["feet"]]

    def solve(self, sl):
        m, d = self.model, self.data
        qv = np.zeros(m.nq)
        qv[6] = 1.0
        v = np.zeros(m.nv)
        acc = np.zeros(m.nv)
        th = sl["thorax"]
        w, vel = np.array(th["w"]), np.array(th["v"])
        v[0:3], v[3:6] = vel, w
        # Pinocchio's base acceleration is the spatial one: classical minus w x v.
        acc[0:3] = np.array(th["a"]) - np.cross(w, vel)
        acc[3:6] = th["alpha"]
        for i, iq, iv, _ in self.act:
            qv[iq] = sl["q"][i]
            v[iv] = sl["qd"][i]
            acc[iv] = sl["qdd"][i]
        m.gravity.linear = np.array(sl["gravity"])
        tau0 = pin.rnea(m, d, qv, v, acc)
        pin.computeJointJacobians(m, d, qv)
        pin.updateFramePlacements(m, d)
        stance = [k for k, s in enumerate(sl["stance"]) if s]
        jt = np.hstack(
            [
                pin.getFrameJacobian(m, d, self.frames[k], pin.LOCAL_WORLD_ALIGNED)[:3].T
                for k in stance
            ]
        )  # nv x 3 ns
        iv = np.array([a[2] for a in self.act])
        kk = np.array([a[3] for a in self.act])
        spring = np.array([sl["ours"]["spring"][a[0]] for a in self.act])
        c = tau0[iv] - spring
        bm = -jt[iv]
        e = jt[:6]
        wgt = 1.0 / kk
        h = bm.T @ (wgt[:, None] * bm)
        n, ne = h.shape[0], 6
        kkt = np.zeros((n + ne, n + ne))
        kkt[:n, :n] = h
        kkt[:n, n:] = e.T
        kkt[n:, :n] = e
        rhs = np.concatenate([-bm.T @ (wgt * c), tau0[:6]])
        g = np.linalg.solve(kkt, rhs)[:n]
        t = c + bm @ g
        return 0.5 * float(np.sum(wgt * t * t)), g, stance


# ---------------------------------------------------------------- reference IK (Python)
def reference_ik(model, data, leg, joints, rest, length, targets):
    """Newton / pseudo-inverse on the foot position with the spare DoF pulled to `rest` in the
    null space, warm-started slice by slice; Pinocchio only for FK and Jacobians."""
    fid = model.getFrameId(f"{leg}_tip")
    idx = [model.idx_qs[model.getJointId(n)] for n in joints]
    q = np.zeros(model.nq)
    qa = np.array(rest, dtype=float)
    out = []
    for tgt in targets:
        for _ in range(200):
            q[idx] = qa
            pin.forwardKinematics(model, data, q)
            pin.updateFramePlacement(model, data, fid)
            e = np.array(tgt) - data.oMf[fid].translation
            jac = pin.computeFrameJacobian(model, data, q, fid, pin.LOCAL_WORLD_ALIGNED)[:3, idx]
            jp = np.linalg.pinv(jac)
            dq = jp @ e + (np.eye(len(idx)) - jp @ jac) @ (np.array(rest) - qa)
            qa = qa + dq
            if np.linalg.norm(e) < 1e-9 * length and np.linalg.norm(dq) < 1e-10:
                break
        out.append(qa.copy())
    return np.array(out)


def firmware_rows(log):
    """Measured bus rates from the firmware's simulated-wire test output, and the wire limit:
    a walking cycle is 622 bytes (Sync Write of 22 x 4-byte goals = 124, Sync Read request of 22
    IDs = 36, 22 status packets of 10 data bytes = 22 x 21), 10 bits per byte, return delay 0."""
    cycle_bytes = 124 + 36 + 22 * 21
    measured = {}
    if log and os.path.exists(log):
        for line in open(log):
            mt = re.search(r"(\d+) baud at (\d+) Hz: ([\d.]+) Hz measured, longest cycle (\d+) us", line)
            if mt:
                measured[int(mt.group(1))] = (float(mt.group(3)), int(mt.group(4)), int(mt.group(2)))
    rows = []
    for baud in [57_600, 115_200, 1_000_000, 2_000_000, 3_000_000, 4_000_000, 4_500_000]:
        wire = baud / (10 * cycle_bytes)
        rows.append((baud, wire, measured.get(baud)))
    return cycle_bytes, rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--slsqp-slices", type=int, default=5)
    ap.add_argument("--firmware", default=None)
    args = ap.parse_args()
    doc = json.load(open(os.path.join(args.out, "export.json")))
    slices = doc["slices"]
    ours = doc["ours"]
    ns = len(slices)
    res = {"versions": {"numpy": np.__version__, "scipy": scipy.__version__,
                        "clarabel": clarabel.__version__, "pinocchio": pin.__version__}}

    probs = [full_problem(s) for s in slices]
    ours_v = np.array([s["ours"]["v_star"] for s in slices])
    ours_t = np.array([s["ours"]["time_s"] for s in slices])
    print(f"model {doc['model']}: {doc['n_bodies']} bodies, {doc['n_joints']} joints, "
          f"full system {probs[0][3].shape[0]}-{max(p[3].shape[0] for p in probs)} rows x "
          f"{probs[0][3].shape[1]} unknowns, {ns} slices")

    # Clarabel (Python) on the full system, every slice.
    cl_t, cl_gap = [], []
    for (p, q, c, a, b), v in zip(probs, ours_v):
        t, (x, status) = best_time(lambda: solve_clarabel(p, q, a, b), 1, 3)
        assert status == "Solved", status
        cl_t.append(t)
        cl_gap.append(abs(objective(p, q, c, x) - v) / abs(v))
    cl_t = np.array(cl_t)

    # SLSQP on a handful of evenly spread slices.
    pick = np.linspace(0, ns - 1, args.slsqp_slices).round().astype(int)
    sq_t, sq_gap, sq_nit = [], [], []
    for i in pick:
        p, q, c, a, b = probs[i]
        t0 = time.thread_time()
        x, r = solve_slsqp(p, q, c, a, b)
        sq_t.append(time.thread_time() - t0)
        sq_gap.append(abs(objective(p, q, c, x) - ours_v[i]) / abs(ours_v[i]))
        sq_nit.append(int(r.nit))
        nfeet = sum(slices[i]["stance"])
        print(f"  SLSQP slice {i:3d} ({nfeet} feet down): {sq_t[-1]*1e3:7.1f} ms, {r.nit} it, "
              f"V* {objective(p, q, c, x):.9e} J vs ours {ours_v[i]:.9e} J, rel gap {sq_gap[-1]:.1e}, "
              f"{r.message}")
    sq_t = np.array(sq_t)

    # NumPy reduced problem with Pinocchio RNEA, every slice.
    red = Reduced(os.path.join(args.out, "model.urdf"), doc)
    rd_t, rd_gap, grf_err = [], [], []
    for s, v in zip(slices, ours_v):
        t, (val, g, stance) = best_time(lambda: red.solve(s), 5, 3)
        rd_t.append(t)
        rd_gap.append(abs(val - v) / abs(v))
        ours_g = np.concatenate([s["ours"]["grf"][k] for k in stance])
        grf_err.append(np.max(np.abs(g - ours_g)) / np.max(np.abs(ours_g)))
    rd_t = np.array(rd_t)

    # One leg: our RNEA vs Pinocchio's on the exported one-leg URDF (fixed thorax).
    leg_rows = []
    for lg in doc["legs"]:
        m = pin.buildModelFromUrdf(os.path.join(args.out, lg["urdf"]))
        d = m.createData()
        act = [(i, m.idx_qs[m.getJointId(j["name"])]) for i, j in enumerate(lg["joints"])
               if j["actuated"]]
        err, tp = 0.0, None
        for case in lg["cases"]:
            qv, v, a = np.zeros(m.nq), np.zeros(m.nv), np.zeros(m.nv)
            for i, k in act:
                qv[k], v[k], a[k] = case["q"][i], case["qd"][i], case["qdd"][i]
            m.gravity.linear = np.array(case["gravity"])
            tau = pin.rnea(m, d, qv, v, a)
            ours_tau = np.array([case["tau"][i] for i, _ in act])
            err = max(err, np.max(np.abs(tau[[k for _, k in act]] - ours_tau)) /
                      np.max(np.abs(ours_tau)))
            if tp is None:
                tp, _ = best_time(lambda: pin.rnea(m, d, qv, v, a), 20000, 5)
        leg_rows.append((lg["leg"], m.nv, tp, lg["time_s"], err))

    # IK of the whole step cycle: Python reference vs ours.
    mk = pin.buildModelFromUrdf(os.path.join(args.out, "model.urdf"))
    dk = mk.createData()
    legi = {leg: k for k, leg in enumerate(doc["plan_legs"])}

    def ik_all():
        return [reference_ik(mk, dk, e["leg"], e["joints"], e["rest"], e["length"],
                             [s["feet_targets"][legi[e["leg"]]] for s in slices])
                for e in doc["ik"]]

    t0 = time.thread_time()
    ref = ik_all()
    ik_t = time.thread_time() - t0
    ik_err = max(float(np.max(np.abs(r - np.array(e["q"])))) for r, e in zip(ref, doc["ik"]))

    cycle_bytes, fw = firmware_rows(args.firmware)

    # ---------------------------------------------------------------- the table
    our_slice = float(np.median(ours_t))
    rows = [
        ("per slice: SciPy SLSQP, full system", f"{len(pick)} slices", np.median(sq_t), our_slice,
         f"max rel V* gap {max(sq_gap):.1e}"),
        ("per slice: Clarabel (Python), full system", f"{ns} slices", np.median(cl_t), our_slice,
         f"max rel V* gap {max(cl_gap):.1e}"),
        ("per slice: NumPy reduced + Pinocchio RNEA", f"{ns} slices", np.median(rd_t), our_slice,
         f"max rel V* gap {max(rd_gap):.1e}, GRF {max(grf_err):.1e}"),
        ("step cycle: SLSQP (estimate: median x slices)", f"{ns} slices", np.median(sq_t) * ns,
         ours["cycle_s"], "extrapolated, not run"),
        ("step cycle: Clarabel (Python), full system", f"{ns} slices", cl_t.sum(), ours["cycle_s"],
         "sum of per-slice medians"),
        ("step cycle: NumPy reduced + Pinocchio RNEA", f"{ns} slices", rd_t.sum(), ours["cycle_s"],
         "sum of per-slice medians"),
    ]
    for leg, nv, tp, to, err in leg_rows:
        rows.append((f"one leg RNEA ({leg}, {nv} DoF): Pinocchio", "1 call", tp, to,
                     f"max rel torque diff {err:.1e}"))
    rows.append(("IK of the step cycle: Python reference", f"{ns} slices x 6 legs", ik_t,
                 ours["ik_cycle_s"], f"max joint diff {ik_err:.1e} rad"))

    def fmt(t):
        return f"{t*1e6:10.1f} us" if t < 1e-3 else f"{t*1e3:10.2f} ms" if t < 1 else f"{t:10.2f} s "

    print()
    print(f"| {'comparison':48} | {'inputs':20} | {'peer':>13} | {'ours':>13} | {'peer/ours':>9} | agreement |")
    print(f"|{'-'*50}|{'-'*22}|{'-'*15}|{'-'*15}|{'-'*11}|-----------|")
    for name, inp, tp, to, agree in rows:
        print(f"| {name:48} | {inp:20} | {fmt(tp):>13} | {fmt(to):>13} | {tp/to:9.1f} | {agree} |")
    print()
    print(f"ours, other variants: cycle with Clarabel.rs {fmt(ours['cycle_clarabel_s'])}, "
          f"with friction cones + push-only {fmt(ours['cycle_cone_s'])}, whole plan (posture + IK + "
          f"derivatives) {fmt(ours['plan_s'])}")
    print()
    print(f"firmware bus cycle ({cycle_bytes} bytes per walking cycle, 10 bits/byte, return delay 0):")
    print("| baud | wire-limited rate | measured rate (simulated wire) | longest cycle | measured / wire |")
    print("|---|---|---|---|---|")
    for baud, wire, meas in fw:
        if meas:
            rate, busy, hz = meas
            print(f"| {baud} | {wire:.1f} Hz | {rate:.2f} Hz (configured {hz} Hz) | {busy} us | "
                  f"{rate/wire:.2f} (free-running {1e6/busy/wire:.2f}) |")
        else:
            print(f"| {baud} | {wire:.1f} Hz | not measured | - | - |")

    targets = [
        ("ours >= 1000x faster than SLSQP per slice, same optimum (1e-6)",
         np.median(sq_t) / our_slice >= 1000 and max(sq_gap) <= 1e-6),
        ("ours >= 10x faster than Python Clarabel on the full system",
         np.median(cl_t) / our_slice >= 10),
        ("ours faster than the NumPy reduced solve", np.median(rd_t) / our_slice > 1),
    ]
    print()
    for t, ok in targets:
        print(f"target: {t}: {'MET' if ok else 'NOT MET'}")
    res.update({
        "slsqp": {"slices": pick.tolist(), "time_s": sq_t.tolist(), "gap": sq_gap, "nit": sq_nit},
        "clarabel_time_s": cl_t.tolist(), "clarabel_gap": cl_gap,
        "reduced_time_s": rd_t.tolist(), "reduced_gap": rd_gap,
        "legs": leg_rows, "ik": {"time_s": ik_t, "max_diff": ik_err},
        "ours": ours, "ours_slice_s": ours_t.tolist(), "targets": targets,
        "scaling": doc.get("scaling"),
    })
    json.dump(res, open(os.path.join(args.out, "results.json"), "w"), default=float, indent=1)
    if doc.get("scaling"):
        sc = doc["scaling"]
        print("\nscaling (ours):")
        for r in sc["slices_per_step"]:
            print(f"  {r['slices']:4d} slices/step: plan {fmt(r['plan_s'])}, dynamics {fmt(r['dynamics_s'])}")
        for r in sc["legs"]:
            print(f"  {r['legs']} legs ({r['joints']} joints, fixed thorax, all feet down): "
                  f"slice {fmt(r['slice_s'])}")
        for r in sc["steps"]:
            print(f"  {r['steps']} steps ({r['slices']} slices): dynamics {fmt(r['dynamics_s'])}")


if __name__ == "__main__":
    main()

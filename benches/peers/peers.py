"""Side-by-side comparison of the crate with heyoka, REBOUND (+REBOUNDx) and SciPy.

Every solver starts from the same double-precision state, integrates over the same span (100
periods) and is scored by the same error: the maximum norm of the difference between its final
state (q, p) and a reference. The reference is computed independently of every solver compared, in
extended precision:

* Kepler: the analytical solution (Kepler's equation) in mpmath at 50 digits;
* pendulum: the analytical solution by Jacobi elliptic functions in mpmath at 50 digits;
* Kepler + J2: heyoka's Taylor method in quadruple precision (real128) at tolerance 1e-32, checked
  against the same at 1e-28 (the difference is printed).

Each solver runs over a sweep of its accuracy knob (tolerance, IAS15 epsilon, WHFast step); its
time to reach a final error ≤ target is its fastest run with error ≤ target. The ratio of a row
is the crate's fastest time / the fastest peer's time at that target (< 1: the crate is ahead).
Times are best of `RUNS` runs (one run when a single run exceeds `SLOW` seconds); heyoka's
compilation and the crate's recording are not counted (they are reported apart).

Usage: python peers.py <crate-example-binary> <output-dir> [problem-filter]
"""

import json
import math
import os
import subprocess
import sys
import time

import mpmath as mp
import numpy as np

RUNS = 3
SLOW = 2.0
TARGETS = [1e-6, 1e-9, 1e-12]
TOLS = [1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13, 1e-14, 1e-15]
PERIODS = 100

mp.mp.dps = 50


# --------------------------------------------------------------------------------------------
# Problems
# --------------------------------------------------------------------------------------------


def kepler_problem(e):
    q = [1.0 - e, 0.0]
    p = [0.0, math.sqrt((1.0 + e) / (1.0 - e))]
    t1 = PERIODS * 2.0 * math.pi
    return dict(name=f"kepler_e{e}", kind="kepler", label=f"Kepler e = {e}", dim=2,
                x0=q + p, t1=t1, param=None, targets_nbody=True)


def j2_problem(j2, e, a=2.0, inc=0.5):
    r = a * (1.0 - e)
    v = math.sqrt((1.0 + e) / r)
    q = [r, 0.0, 0.0]
    p = [0.0, v * math.cos(inc), v * math.sin(inc)]
    t1 = PERIODS * 2.0 * math.pi * a ** 1.5
    return dict(name=f"j2_{j2:g}_e{e}", kind="j2", label=f"Kepler + J2 = {j2:g}, e = {e}",
                dim=3, x0=q + p, t1=t1, param=j2, targets_nbody=True)


def pendulum_problem(q0):
    k = mp.sin(mp.mpf(q0) / 2)
    t1 = float(PERIODS * 4 * mp.ellipk(k * k))
    return dict(name=f"pendulum_q{q0}", kind="pendulum", label=f"pendulum q0 = {q0}", dim=1,
                x0=[q0, 0.0], t1=t1, param=None, targets_nbody=False)


PROBLEMS = (
    [j2_problem(1e-3, e) for e in (0.1, 0.7)]
    + [j2_problem(1e-6, e) for e in (0.1, 0.7)]
    + [pendulum_problem(q0) for q0 in (0.1, 1.0, 3.0, 3.14159)]
    + [kepler_problem(e) for e in (0.0, 0.5, 0.9, 0.99)]
)


# --------------------------------------------------------------------------------------------
# References
# --------------------------------------------------------------------------------------------


def kepler_reference(x0, t1):
    """Planar Kepler (mu = 1) from the exact double state by Kepler's equation, 50 digits."""
    qx, qy, px, py = (mp.mpf(v) for v in x0)
    t = mp.mpf(t1)
    r0 = mp.sqrt(qx * qx + qy * qy)
    v2 = px * px + py * py
    a = 1 / (2 / r0 - v2)
    n = a ** mp.mpf(-1.5)
    rv = qx * px + qy * py
    ecosE = 1 - r0 / a
    esinE = rv / mp.sqrt(a)
    E0 = mp.atan2(esinE, ecosE)
    M0 = E0 - esinE
    M = M0 + n * t
    e = mp.sqrt(ecosE ** 2 + esinE ** 2)
    # Newton on E - e sin E = M from E = M (+ e sign) at 50 digits.
    E = M + (e if mp.sin(M) >= 0 else -e) * 0.85
    for _ in range(200):
        dE = (E - e * mp.sin(E) - M) / (1 - e * mp.cos(E))
        E -= dE
        if abs(dE) < mp.mpf(10) ** (-45):
            break
    # f and g functions (Danby 6.8): q = f q0 + g p0, p = fdot q0 + gdot p0.
    dE = E - E0
    r = a + (r0 - a) * mp.cos(dE) + rv * mp.sqrt(a) * mp.sin(dE)
    f = 1 - a / r0 * (1 - mp.cos(dE))
    g = t - a ** mp.mpf(1.5) * (dE - mp.sin(dE))
    fd = -mp.sqrt(a) / (r * r0) * mp.sin(dE)
    gd = 1 - a / r * (1 - mp.cos(dE))
    return [float(f * qx + g * px), float(f * qy + g * py),
            float(fd * qx + gd * px), float(fd * qy + gd * py)]


def pendulum_reference(x0, t1):
    """H = p^2/2 + 1 - cos q from (q0, 0): sin(q/2) = k sn(t + K, k), k = sin(q0/2), 50 digits."""
    q0 = mp.mpf(x0[0])
    k = mp.sin(q0 / 2)
    m = k * k
    u = mp.mpf(t1) + mp.ellipk(m)
    sn, cn, dn = (mp.ellipfun(w, u, m=m) for w in ("sn", "cn", "dn"))
    s = k * sn
    q = 2 * mp.asin(s)
    p = 2 * k * cn * dn / mp.sqrt(1 - s * s)
    return [float(q), float(p)]


def j2_reference(x0, t1, j2, tol):
    import heyoka as hy

    R = hy.real128
    ta = hy.taylor_adaptive(j2_heyoka_system(j2, R), np.array(x0, dtype=R), tol=R(tol), fp_type=R)
    ta.propagate_until(R(t1))
    return [float(v) for v in ta.state]


def reference(pb):
    if pb["kind"] == "kepler":
        return kepler_reference(pb["x0"], pb["t1"]), "Kepler's equation, mpmath 50 digits"
    if pb["kind"] == "pendulum":
        return pendulum_reference(pb["x0"], pb["t1"]), "Jacobi elliptic functions, mpmath 50 digits"
    ref = j2_reference(pb["x0"], pb["t1"], pb["param"], "1e-32")
    check = j2_reference(pb["x0"], pb["t1"], pb["param"], "1e-28")
    d = max(abs(a - b) for a, b in zip(ref, check))
    return ref, f"heyoka real128 tol 1e-32 (vs tol 1e-28: {d:.1e})"


# --------------------------------------------------------------------------------------------
# Solvers
# --------------------------------------------------------------------------------------------


def timed(fn):
    """Best wall time of `fn()` over RUNS runs (one if a run exceeds SLOW), and its result."""
    best, out = math.inf, None
    for i in range(RUNS):
        t = time.perf_counter()
        out = fn()
        dt = time.perf_counter() - t
        best = min(best, dt)
        if dt > SLOW:
            break
    return best, out


def j2_heyoka_system(j2, fp=float):
    import heyoka as hy

    x, y, z, vx, vy, vz = hy.make_vars("x", "y", "z", "vx", "vy", "vz")
    r2 = x * x + y * y + z * z
    # V = -1/r + (J2 R^2 / 2)(3 z^2/r^2 - 1)/r^3, mu = R = 1: the same H as the crate's.
    c = fp(j2) / 2 if fp is float else fp(str(j2)) / 2
    V = -r2 ** -0.5 + c * (3 * z * z / r2 - 1) * (r2) ** -1.5
    return [(x, vx), (y, vy), (z, vz),
            (vx, -hy.diff(V, x)), (vy, -hy.diff(V, y)), (vz, -hy.diff(V, z))]


def heyoka_system(pb):
    import heyoka as hy

    if pb["kind"] == "kepler":
        x, y, vx, vy = hy.make_vars("x", "y", "vx", "vy")
        r3 = (x * x + y * y) ** -1.5
        return [(x, vx), (y, vy), (vx, -x * r3), (vy, -y * r3)]
    if pb["kind"] == "pendulum":
        q, p = hy.make_vars("q", "p")
        return [(q, p), (p, -hy.sin(q))]
    return j2_heyoka_system(pb["param"])


def run_heyoka(pb):
    import heyoka as hy

    sysm = heyoka_system(pb)
    out = []
    for tol in TOLS:
        t = time.perf_counter()
        ta = hy.taylor_adaptive(sysm, pb["x0"], tol=tol)
        compile_s = time.perf_counter() - t

        def go():
            ta.time = 0.0
            ta.state[:] = pb["x0"]
            res = ta.propagate_until(pb["t1"])
            return res[3], list(ta.state)

        dt, (steps, x) = timed(go)
        out.append(dict(method="heyoka (Taylor)", tol=tol, seconds=dt, steps=int(steps), x=x,
                        compile_seconds=compile_s))
    return out


def rebound_sim(pb, integrator):
    import rebound

    sim = rebound.Simulation()
    sim.G = 1.0
    sim.add(m=1.0)
    d = pb["dim"]
    q, p = pb["x0"][:d], pb["x0"][d:]
    q3 = list(q) + [0.0] * (3 - d)
    p3 = list(p) + [0.0] * (3 - d)
    sim.add(m=0.0, x=q3[0], y=q3[1], z=q3[2], vx=p3[0], vy=p3[1], vz=p3[2])
    sim.integrator = integrator
    rx = None
    if pb["kind"] == "j2":
        import reboundx

        rx = reboundx.Extras(sim)
        gh = rx.load_force("gravitational_harmonics")
        rx.add_force(gh)
        sim.particles[0].params["J2"] = pb["param"]
        sim.particles[0].params["R_eq"] = 1.0
    return sim, rx


def rebound_state(sim, pb):
    d = pb["dim"]
    s, t = sim.particles[0], sim.particles[1]
    q = [t.x - s.x, t.y - s.y, t.z - s.z][:d]
    p = [t.vx - s.vx, t.vy - s.vy, t.vz - s.vz][:d]
    return q + p


def run_rebound(pb):
    out = []
    period = pb["t1"] / PERIODS
    for eps in [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9]:
        def go():
            sim, rx = rebound_sim(pb, "ias15")
            sim.integrator.epsilon = eps
            sim.integrate(pb["t1"], exact_finish_time=1)
            return sim.steps_done, rebound_state(sim, pb)

        dt, (steps, x) = timed(go)
        out.append(dict(method="REBOUND IAS15", tol=eps, seconds=dt, steps=steps, x=x))
    for n in [30, 100, 300, 1000, 3000]:
        def go():
            sim, rx = rebound_sim(pb, "whfast")
            sim.dt = period / n
            sim.integrator.corrector = 17
            sim.integrator.safe_mode = 0
            sim.integrate(pb["t1"], exact_finish_time=1)
            sim.synchronize()
            return sim.steps_done, rebound_state(sim, pb)

        dt, (steps, x) = timed(go)
        out.append(dict(method="REBOUND WHFast (corrector 17)", tol=1.0 / n, seconds=dt,
                        steps=steps, x=x))
    return out


def scipy_field(pb):
    if pb["kind"] == "kepler":
        def f(t, s):
            x, y, vx, vy = s
            r3 = (x * x + y * y) ** -1.5
            return [vx, vy, -x * r3, -y * r3]
    elif pb["kind"] == "pendulum":
        def f(t, s):
            return [s[1], -math.sin(s[0])]
    else:
        c = pb["param"] / 2

        def f(t, s):
            x, y, z, vx, vy, vz = s
            r2 = x * x + y * y + z * z
            ir2 = 1.0 / r2
            ir3 = ir2 ** 1.5
            ir5 = ir3 * ir2
            zz = z * z * ir2
            # a = -grad V, V = -1/r + c (3 z^2/r^2 - 1)/r^3
            k = -ir3 + c * ir5 * (15.0 * zz - 3.0)
            return [vx, vy, vz, k * x, k * y, k * z - 6.0 * c * ir5 * z]
    return f


def run_scipy(pb):
    from scipy.integrate import solve_ivp

    f = scipy_field(pb)
    out = []
    for tol in [t for t in TOLS if t >= 1e-12]:
        def go():
            sol = solve_ivp(f, (0.0, pb["t1"]), pb["x0"], method="DOP853", rtol=tol, atol=tol)
            return sol.nfev, list(sol.y[:, -1])

        dt, (nfev, x) = timed(go)
        out.append(dict(method="SciPy DOP853", tol=tol, seconds=dt, steps=int(nfev) // 12,
                        x=x))
    return out


def run_crate(pb, binary):
    args = [binary, pb["kind"]]
    if pb["kind"] == "j2":
        args.append(repr(pb["param"]))
    args += [str(RUNS), ",".join(repr(t) for t in TOLS), repr(pb["t1"])]
    args += [repr(v) for v in pb["x0"]]
    res = subprocess.run(args, capture_output=True, text=True, check=True)
    if res.stderr.strip():
        print("   crate:", res.stderr.strip().replace("\n", "\n   crate: "))
    rows = json.loads(res.stdout)
    for r in rows:
        r["method"] = r["method"].split(" (order")[0]
    return rows


# --------------------------------------------------------------------------------------------
# Table and figures
# --------------------------------------------------------------------------------------------


def fastest(runs, target):
    ok = [r for r in runs if r["error"] <= target]
    return min(ok, key=lambda r: r["seconds"]) if ok else None


def fmt_t(s):
    return f"{s * 1e3:.3g} ms" if s >= 1e-3 else f"{s * 1e6:.3g} µs"


def main():
    binary, outdir = sys.argv[1], sys.argv[2]
    only = sys.argv[3] if len(sys.argv) > 3 else ""
    os.makedirs(outdir, exist_ok=True)
    import heyoka
    import rebound
    import scipy

    lines = [
        "| problem | reference | " + " | ".join(f"{t:g}" for t in TARGETS) + " |",
        "|---|---|" + "---|" * len(TARGETS),
    ]
    details = []
    for pb in PROBLEMS:
        if only and only not in pb["name"]:
            continue
        print(f"== {pb['label']}  (t1 = {pb['t1']!r})", flush=True)
        ref, how = reference(pb)
        runs = run_crate(pb, binary) + run_heyoka(pb)
        if pb["targets_nbody"]:
            runs += run_rebound(pb)
        runs += run_scipy(pb)
        for r in runs:
            r["error"] = float(max(abs(a - b) for a, b in zip(r["x"], ref)))
            if not math.isfinite(r["error"]):
                r["error"] = math.inf
        with open(os.path.join(outdir, f"{pb['name']}.csv"), "w") as fh:
            fh.write("method,knob,steps,seconds,error\n")
            for r in runs:
                fh.write(f"{r['method']},{r['tol']!r},{r['steps']},{r['seconds']!r},"
                         f"{r['error']!r}\n")
        cells = []
        for target in TARGETS:
            ours = fastest([r for r in runs if r["method"].startswith("crate")], target)
            peer = fastest([r for r in runs if not r["method"].startswith("crate")], target)
            if ours and peer:
                cells.append(f"**{ours['seconds'] / peer['seconds']:.2f}** "
                             f"({ours['method'][6:]} {fmt_t(ours['seconds'])} / "
                             f"{peer['method']} {fmt_t(peer['seconds'])})")
            elif ours:
                cells.append(f"only ours ({ours['method'][6:]} {fmt_t(ours['seconds'])})")
            elif peer:
                cells.append(f"only peers ({peer['method']} {fmt_t(peer['seconds'])})")
            else:
                cells.append("nobody")
        lines.append(f"| {pb['label']} | {how} | " + " | ".join(cells) + " |")
        for r in runs:
            if r["method"] in ("crate Taylor", "heyoka (Taylor)") and r["tol"] in TARGETS:
                details.append(
                    f"| {pb['label']} | {r['method']} | {r['tol']:g} | {r['steps']} | "
                    f"{fmt_t(r['seconds'])} | {r['seconds'] / max(r['steps'], 1) * 1e6:.3f} | "
                    f"{r['error']:.2e} |")
        print("  ", lines[-1], flush=True)
        plot(pb, runs, outdir)
    load = open("/proc/loadavg").read().split()[:3]
    head = [
        "# The crate against heyoka, REBOUND and SciPy",
        "",
        f"heyoka {heyoka.__version__}, REBOUND {rebound.__version__}, SciPy {scipy.__version__}; "
        f"load average at the end {' '.join(load)}; {os.cpu_count()} cores.",
        "",
        "Cell: crate's fastest time / fastest peer's time to a final error ≤ target "
        "(max norm over (q, p) at t1 = 100 periods); < 1: the crate is ahead.",
        "",
    ]
    tail = [
        "",
        "## Taylor method against heyoka at equal tolerance",
        "",
        "| problem | solver | tol | steps | time | µs/step | error |",
        "|---|---|---|---|---|---|---|",
    ] + details
    with open(os.path.join(outdir, "peers.md"), "w") as fh:
        fh.write("\n".join(head + lines + tail) + "\n")
    print("\n".join(head + lines + tail))


def plot(pb, runs, outdir):
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, ax = plt.subplots(figsize=(9.0, 4.4))
    for m in dict.fromkeys(r["method"] for r in runs):
        rs = sorted((r for r in runs if r["method"] == m), key=lambda r: r["seconds"])
        ax.loglog([r["seconds"] for r in rs], [max(r["error"], 1e-17) for r in rs], "o-",
                  label=m, ms=3)
    for t in TARGETS:
        ax.axhline(t, color="grey", lw=0.5, ls=":")
    ax.set_xlabel("wall time of the 100-period run [s]")
    ax.set_ylabel("final error, max |x - x_ref|")
    ax.set_title(pb["label"])
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, f"{pb['name']}.svg"))
    plt.close(fig)


if __name__ == "__main__":
    main()

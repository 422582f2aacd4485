"""The outer Solar System beside REBOUND's WHFast: energy error against cost.

The problem is the crate's `systems::outer_solar_system()` (Hairer, Lubich & Wanner, GNI §I.2.4:
the Sun with the inner planets' mass and Jupiter, Saturn, Uranus, Neptune; G in AU³/(M☉ day²),
time in days). Its initial state is printed by the crate binary (`peers_crate nbody state`), so
REBOUND starts from the same doubles: the same G, masses and positions, and the velocities v = p/m
of the crate's momenta.

Compared at the same step h and span, with the same coordinates and corrector order:

* Jacobi coordinates, no corrector: the crate's `PlanetaryWisdomHolman` with `SABA1`
  (drift–kick–drift, WHFast's map) and WHFast (`coordinates="jacobi"`, `corrector=0`); the
  crate's kick–drift–kick `WisdomHolman::WH` beside them (its energy error at the outputs is about
  twice the drift–kick–drift one: the leading term of the modified Hamiltonian, `{A,{A,B}}`, has
  the coefficient 1/12 instead of 1/24);
* Jacobi coordinates, order-17 symplectic corrector (applied at every output): the crate's
  `WisdomHolman::WH.with_corrector(17)` (kernel SABA1) and WHFast `corrector=17`;
* democratic heliocentric coordinates, no corrector: the crate's kick–drift–kick map (Duncan,
  Levison & Lee 1998) and WHFast `coordinates="democraticheliocentric"` (REBOUND's WHDS split of
  Hernandez & Dehnen 2017 is run beside it).

Both codes run `OUTPUTS` equal chunks of the span, synchronise (the corrector, the coordinate
maps) at each output and evaluate the energy there; the error of a run is the relative energy error
|E(t) − E₀|/|E₀|, its maximum over the outputs and its final value. Each code's final energy is
checked against the same energy formula evaluated here (`math.fsum`) on its final state. Wall time:
best of `RUNS` runs (one when a run takes longer than `SLOW` seconds), the energy evaluations at the
outputs included for both. REBOUND runs with `safe_mode = 0` (no synchronisation between outputs),
its fastest setting.

Usage: python nbody.py <crate-example-binary> <output-dir>
Environment: NBODY_SPAN (days, default 3.6525e7 = 10⁵ years) for the sweep of h; NBODY_LONG
(default 1: one run of NBODY_LONG_SPAN days, default 3.6525e8 = 10⁶ years, at h = 20 days
per method, 0 to skip); NBODY_LONG_KEYS (a
comma-separated list of method keys for the long run, default every method).
"""

import json
import math
import os
import resource
import subprocess
import sys
import time

RUNS = 3
SLOW = 30.0
YEAR = 365.25
SPAN = float(os.environ.get("NBODY_SPAN", 1e5 * YEAR))
LONG_SPAN = float(os.environ.get("NBODY_LONG_SPAN", 1e6 * YEAR))
LONG_H = 20.0
HS = [10.0, 20.0, 40.0, 80.0]
OUTPUTS = 1000
TARGETS = [1e-6, 1e-7, 1e-8, 1e-9, 1e-10]

# key, label, the crate's method (peers_crate nbody), REBOUND's (coordinates, corrector), and the
# key of the REBOUND run a crate-only row is compared with.
METHODS = [
    dict(key="jacobi", label="Jacobi, drift–kick–drift", crate="jacobi-dkd",
         rebound=("jacobi", 0)),
    dict(key="jacobi17", label="Jacobi + corrector 17", crate="jacobi17", rebound=("jacobi", 17)),
    dict(key="dh", label="democratic heliocentric", crate="dh",
         rebound=("democraticheliocentric", 0)),
    dict(key="jacobi-kdk", label="Jacobi, kick–drift–kick (crate's WH) vs WHFast Jacobi",
         crate="jacobi", rebound=None, peer="jacobi"),
    dict(key="whds", label="WHDS (REBOUND only)", crate=None, rebound=("whds", 0)),
]


def energy(G, masses, x, v):
    """H = Σ m|v|²/2 − Σ_{i<j} G mᵢ mⱼ / |xᵢ − xⱼ|, summed by math.fsum."""
    terms = [0.5 * m * sum(c * c for c in vi) for m, vi in zip(masses, v)]
    n = len(masses)
    for i in range(n):
        for j in range(i + 1, n):
            r = math.sqrt(sum((a - b) ** 2 for a, b in zip(x[i], x[j])))
            terms.append(-G * masses[i] * masses[j] / r)
    return math.fsum(terms)


def timed(fn, runs=RUNS):
    """Best wall time and best CPU time of `fn()` over `runs` runs, and its result."""
    best, best_cpu, out = math.inf, math.inf, None
    for _ in range(runs):
        t, c = time.perf_counter(), time.process_time()
        out = fn()
        dt = time.perf_counter() - t
        best_cpu = min(best_cpu, time.process_time() - c)
        best = min(best, dt)
        if dt > SLOW:
            break
    return best, best_cpu, out


def rebound_run(state, coords, corrector, h, span, runs):
    import rebound

    chunk = max(1, round(span / (OUTPUTS * h)))
    G, masses = state["G"], state["masses"]

    def go():
        sim = rebound.Simulation()
        sim.G = G
        for m, x, v in zip(masses, state["x"], state["v"]):
            sim.add(m=m, x=x[0], y=x[1], z=x[2], vx=v[0], vy=v[1], vz=v[2])
        sim.integrator = "whfast"
        sim.integrator.coordinates = coords
        sim.integrator.corrector = corrector
        sim.integrator.safe_mode = 0
        sim.dt = h
        e0 = sim.energy()
        worst = 0.0
        for k in range(1, OUTPUTS + 1):
            # Stops after exactly k·chunk steps (no step shortened to land on the output time).
            sim.integrate((k * chunk - 0.5) * h, exact_finish_time=0)
            sim.synchronize()
            worst = max(worst, abs((sim.energy() - e0) / e0))
        ps = sim.particles
        x = [[p.x, p.y, p.z] for p in ps]
        v = [[p.vx, p.vy, p.vz] for p in ps]
        return sim.steps_done, worst, abs((sim.energy() - e0) / e0), x, v

    dt, cpu, (steps, worst, fin, x, v) = timed(go, runs)
    assert steps == OUTPUTS * chunk, (steps, OUTPUTS * chunk)
    e0 = energy(G, masses, state["x"], state["v"])
    check = abs((energy(G, masses, x, v) - e0) / e0)
    return dict(code="REBOUND", h=h, steps=steps, seconds=dt, cpu=cpu, max_energy=worst,
                final_energy=fin, final_check=check)


def crate_run(binary, state, method, h, span, runs):
    """One step size: the crate binary runs `runs` times and reports its best wall time; the CPU
    time per run is the child's user + system time over `runs` (process start-up included)."""
    args = [binary, "nbody", str(runs), repr(h), repr(span), str(OUTPUTS), method]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    res = subprocess.run(args, capture_output=True, text=True, check=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime) / runs
    if res.stderr.strip():
        print("   crate:", res.stderr.strip())
    G, masses = state["G"], state["masses"]
    p0 = state["p"]
    e0 = energy(G, masses, state["x"], [[c / m for c in pi] for m, pi in zip(masses, p0)])
    (r,) = json.loads(res.stdout)
    x = [r["x"][3 * i:3 * i + 3] for i in range(len(masses))]
    v = [[c / m for c in r["p"][3 * i:3 * i + 3]] for i, m in enumerate(masses)]
    check = abs((energy(G, masses, x, v) - e0) / e0)
    return dict(code="crate", h=r["h"], steps=r["steps"], seconds=r["seconds"], cpu=cpu,
                max_energy=r["max_energy"], final_energy=r["final_energy"],
                final_check=check, flows=r["flows"], gradients=r["gradients"])


def sweep(binary, state, hs, span, runs, keys=None):
    rows = []
    for m in METHODS:
        if keys and m["key"] not in keys:
            continue
        print(f"== {m['label']}: h = {hs}, span {span:.6g} d", flush=True)
        for h in hs:
            # The two codes one after the other at each h, so that both see the same load.
            pair = []
            if m["crate"]:
                pair.append(crate_run(binary, state, m["crate"], h, span, runs))
            if m["rebound"]:
                pair.append(rebound_run(state, *m["rebound"], h, span, runs))
            for r in pair:
                r.update(key=m["key"], label=m["label"])
                rows.append(r)
                print("  ", fmt_row(r), flush=True)
    return rows


def fmt_row(r):
    return (f"{r['code']:<8} h = {r['h']:>5g} d  {r['steps']:>9} steps  {r['seconds']:8.3f} s  "
            f"{r['seconds'] / r['steps'] * 1e6:6.3f} µs/step  CPU {r['cpu']:8.3f} s  max |ΔE/E| {r['max_energy']:.2e}  "
            f"final {r['final_energy']:.2e} (fsum check {r['final_check']:.2e})")


def fmt_t(s):
    return f"{s:.3g} s" if s >= 1 else f"{s * 1e3:.3g} ms"


def equal_h_table(rows):
    lines = [
        "| coordinates, corrector | h [d] | crate time | REBOUND time | ratio | CPU ratio | "
        "crate µs/step | REBOUND µs/step | crate max / final |ΔE/E| | "
        "REBOUND max / final |ΔE/E| |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for m in METHODS:
        if not m["crate"]:
            continue
        key, label, peer = m["key"], m["label"], m.get("peer", m["key"])
        for h in sorted({r["h"] for r in rows}):
            c = [r for r in rows if r["key"] == key and r["code"] == "crate" and r["h"] == h]
            b = [r for r in rows if r["key"] == peer and r["code"] == "REBOUND" and r["h"] == h]
            if not (c and b):
                continue
            c, b = c[0], b[0]
            lines.append(
                f"| {label} | {h:g} | {fmt_t(c['seconds'])} | {fmt_t(b['seconds'])} | "
                f"**{c['seconds'] / b['seconds']:.2f}** | {c['cpu'] / b['cpu']:.2f} | "
                f"{c['seconds'] / c['steps'] * 1e6:.3f} | "
                f"{b['seconds'] / b['steps'] * 1e6:.3f} | {c['max_energy']:.1e} / "
                f"{c['final_energy']:.1e} | {b['max_energy']:.1e} / {b['final_energy']:.1e} |")
    return lines


def equal_error_table(rows):
    lines = ["| max |ΔE/E| ≤ | crate fastest | REBOUND fastest | ratio | CPU ratio |",
             "|---|---|---|---|---|"]
    for t in TARGETS:
        def fastest(code):
            ok = [r for r in rows if r["code"] == code and r["max_energy"] <= t]
            return min(ok, key=lambda r: r["seconds"]) if ok else None

        c, b = fastest("crate"), fastest("REBOUND")
        cell = lambda r: f"{r['label']}, h = {r['h']:g}: {fmt_t(r['seconds'])}" if r else "none"
        ratio = f"**{c['seconds'] / b['seconds']:.2f}** | {c['cpu'] / b['cpu']:.2f}" if c and b \
            else "— | —"
        lines.append(f"| {t:g} | {cell(c)} | {cell(b)} | {ratio} |")
    return lines


def plot(rows, outdir, span):
    import matplotlib
    import matplotlib.ticker

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9.0, 4.8))
    colours = {"jacobi": "C0", "jacobi17": "C1", "dh": "C2", "jacobi-kdk": "C4", "whds": "C3"}
    for m in METHODS:
        key, label = m["key"], m["label"].split(" vs ")[0]
        for code, style in (("crate", "o-"), ("REBOUND", "s--")):
            rs = sorted((r for r in rows if r["key"] == key and r["code"] == code),
                        key=lambda r: r["seconds"])
            if not rs:
                continue
            ax.loglog([r["seconds"] for r in rs], [r["max_energy"] for r in rs], style,
                      color=colours[key], ms=4, label=f"{code}: {label}")
            for r in (rs if key in ("jacobi", "jacobi17") else []):
                ax.annotate(f"{r['h']:g}", (r["seconds"], r["max_energy"]), fontsize=6,
                            xytext=(3, 3), textcoords="offset points", color=colours[key])
    ax.set_xlabel(f"wall time of the {span / YEAR:.3g}-year run [s] (best of {RUNS})")
    ax.set_ylabel("max relative energy error at 1000 outputs")
    ax.set_title("Outer Solar System, Wisdom–Holman: the crate (solid) and REBOUND WHFast "
                 "(dashed);\nlabels on the Jacobi lines: step h in days", fontsize=9)
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    ax.grid(True, which="major", lw=0.3)
    ax.xaxis.set_major_locator(matplotlib.ticker.LogLocator(subs=(1.0, 2.0, 5.0)))
    ax.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda x, _: f"{x:g}"))
    ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    fig.tight_layout()
    for ext in ("svg", "png"):
        fig.savefig(os.path.join(outdir, f"nbody.{ext}"), dpi=130)
    plt.close(fig)


def main():
    binary, outdir = sys.argv[1], sys.argv[2]
    os.makedirs(outdir, exist_ok=True)
    import rebound

    state = json.loads(subprocess.run([binary, "nbody", "state"], capture_output=True,
                                      text=True, check=True).stdout)
    # The same doubles on both sides: REBOUND's particles hold exactly the crate's x and v.
    sim = rebound.Simulation()
    for m, x, v in zip(state["masses"], state["x"], state["v"]):
        sim.add(m=m, x=x[0], y=x[1], z=x[2], vx=v[0], vy=v[1], vz=v[2])
    same = all([p.x, p.y, p.z, p.vx, p.vy, p.vz, p.m] == x + v + [m] for p, m, x, v in
               zip(sim.particles, state["masses"], state["x"], state["v"]))
    print(f"initial state identical in REBOUND: {same}")
    assert same

    rows = sweep(binary, state, HS, SPAN, RUNS)
    long_rows = []
    if os.environ.get("NBODY_LONG", "1") != "0" and SPAN < LONG_SPAN:
        keys = [k for k in os.environ.get("NBODY_LONG_KEYS", "").split(",") if k]
        long_rows = sweep(binary, state, [LONG_H], LONG_SPAN, 1, keys)
    with open(os.path.join(outdir, "nbody.csv"), "w") as fh:
        fh.write("code,coordinates,h,span,steps,seconds,cpu_seconds,max_energy,final_energy,"
                 "final_check\n")
        for r, span in [(r, SPAN) for r in rows] + [(r, LONG_SPAN) for r in long_rows]:
            fh.write(f"{r['code']},{r['key']},{r['h']!r},{span!r},{r['steps']},"
                     f"{r['seconds']!r},{r['cpu']!r},{r['max_energy']!r},{r['final_energy']!r},"
                     f"{r['final_check']!r}\n")
    plot(rows, outdir, SPAN)
    load = open("/proc/loadavg").read().split()[:3]
    text = [
        "# The outer Solar System: the crate beside REBOUND's WHFast",
        "",
        f"REBOUND {rebound.__version__}; load average at the end {' '.join(load)}; "
        f"{os.cpu_count()} cores. Sun + Jupiter, Saturn, Uranus, Neptune (GNI §I.2.4), the same "
        f"initial doubles; {OUTPUTS} outputs (synchronisation and energy at each); "
        f"wall time best of {RUNS} (one run above {SLOW:g} s).",
        "",
        f"## Equal step, {SPAN / YEAR:.3g} years ({SPAN:.6g} days)",
        "",
        "Ratio: the crate's wall time / REBOUND's (< 1: the crate is faster); CPU ratio: the same "
        "with CPU times (user + system; the crate's includes its process start-up), the steadier "
        "measure on a loaded machine.",
        "",
    ] + equal_h_table(rows) + [
        "",
        f"## Equal energy error, {SPAN / YEAR:.3g} years: fastest run of any method",
        "",
    ] + equal_error_table(rows)
    if long_rows:
        text += ["", f"## {LONG_SPAN / YEAR:.3g} years ({LONG_SPAN:.6g} days), h = {LONG_H:g} d, "
                 "one run each", ""] + equal_h_table(long_rows)
    whds = [r for r in rows + long_rows if r["key"] == "whds"]
    if whds:
        text += ["", "REBOUND WHDS: " + "; ".join(
            f"h = {r['h']:g}: {fmt_t(r['seconds'])}, max |ΔE/E| {r['max_energy']:.1e}"
            for r in whds)]
    worst_check = max(abs(r["final_check"] - r["final_energy"]) for r in rows + long_rows)
    text += ["", f"Largest difference between a code's own final energy error and the fsum "
             f"formula's here: {worst_check:.1e}."]
    with open(os.path.join(outdir, "nbody.md"), "w") as fh:
        fh.write("\n".join(text) + "\n")
    print("\n".join(text))


if __name__ == "__main__":
    main()

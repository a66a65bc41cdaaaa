#!/usr/bin/env python3
"""SciPy side of bench/ceres_vs_scipy.sh: the same sky fits as
bench_ceres_fit (same samples, same start, same residuals
weight * (S F(c) - L), same analytic Jacobian, same tolerance for ftol, xtol, gtol as Ceres'
function, parameter and gradient tolerances) with
scipy.optimize.least_squares, timed (median of repeats) and printed next to
Ceres' figures.  Usage: ceres_vs_scipy.py DIR [repeats]"""
import glob, json, sys, time
import numpy as np
from scipy.optimize import least_squares


def hosek(c, ct, g, cg):
    et = np.exp(c[1] / (ct + 0.01)); eg = np.exp(c[4] * g)
    den = 1 + c[7] ** 2 - 2 * c[7] * cg
    chi = (1 + cg * cg) / den ** 1.5
    dchi = -3 * chi * (c[7] - cg) / den
    root = np.sqrt(ct)
    z = 1 + c[0] * et
    s = c[2] + c[3] * eg + c[5] * cg * cg + c[6] * chi + c[8] * root
    grad = np.stack([et * s, c[0] * et / (ct + 0.01) * s, z, z * eg, z * c[3] * g * eg,
                     z * cg * cg, z * chi, z * c[6] * dchi, z * root], axis=1)
    return z * s, grad


def perez(c, ct, g, cg):
    et = np.exp(c[1] / ct); eg = np.exp(c[3] * g)
    z = 1 + c[0] * et
    s = 1 + c[2] * eg + c[4] * cg * cg
    grad = np.stack([et * s, c[0] * et / ct * s, z * eg, z * c[2] * g * eg, z * cg * cg], axis=1)
    return z * s, grad


def median(values):
    return sorted(values)[len(values) // 2]


def main():
    d = sys.argv[1]
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 7
    print("times: median of %d repeats, wall (and process CPU) milliseconds; speedup = SciPy / Ceres" % repeats)
    print("%-28s %18s %18s %15s  %-20s %-20s %s" % ("problem", "ceres ms (cpu)", "scipy ms (cpu)",
                                                   "speedup (cpu)", "ceres final cost", "scipy final cost",
                                                   "scipy method"))
    for path in sorted(glob.glob(d + "/*.json")):
        p = json.load(open(path))
        data = np.loadtxt(path[:-5] + ".csv", delimiter=",")
        ct, g, cg, L = data[:, 0], data[:, 1], data[:, 2], data[:, 3]
        form = hosek if p["form"] == "hosek" else perez
        w = p["weight"]; start = np.array(p["start"]); nc = len(start) - 1
        fix = p["fix_scale"]

        def unpack(x):
            return (x, start[nc]) if fix else (x[:nc], x[nc])

        def res(x):
            c, S = unpack(x)
            f, _ = form(c, ct, g, cg)
            return w * (S * f - L)

        def jac(x):
            c, S = unpack(x)
            f, grad = form(c, ct, g, cg)
            J = w * S * grad
            return J if fix else np.hstack([J, (w * f)[:, None]])

        x0 = start[:nc].copy() if fix else start.copy()
        # Ceres holds the Perez scale >= 0 (a bound): SciPy needs 'trf' for
        # bounds; the unbounded Hosek fits also run with MINPACK's 'lm'.
        runs = []
        methods = ["trf"] + (["lm"] if fix else [])
        for method in methods:
            tol = p["tolerance"]
            kw = dict(jac=jac, method=method, ftol=tol, xtol=tol, gtol=tol, max_nfev=5000)
            if method == "trf" and not fix:
                lo = np.full(nc + 1, -np.inf); lo[nc] = 0.0
                kw["bounds"] = (lo, np.full(nc + 1, np.inf))
            times, cpus = [], []
            for _ in range(repeats):
                t0, c0 = time.perf_counter(), time.process_time()
                r = least_squares(res, x0, **kw)
                times.append(time.perf_counter() - t0)
                cpus.append(time.process_time() - c0)
            runs.append((median(times), median(cpus), r.cost, method, r.nfev))
        best = min(runs, key=lambda t: t[1])
        tc, cc = p["ceres_seconds"], p["ceres_cpu_seconds"]
        for t, c, cost, method, nfev in runs:
            print("%-28s %8.3f (%7.3f) %8.3f (%7.3f) %5.1fx (%5.1fx)  %-20.12g %-20.12g %s (%d evaluations)%s" % (
                p["name"], 1e3 * tc, 1e3 * cc, 1e3 * t, 1e3 * c, t / tc, c / cc,
                p["ceres_final_cost"], cost, method, nfev,
                "  <- fastest SciPy" if (len(runs) > 1 and c == best[1]) else ""))
        if "truth" in p:
            # a recovery: the cost at the generating coefficients through
            # each side's own evaluator is the rounding floor it can reach
            truth = np.array(p["truth"])
            x_truth = truth[:nc] if fix else truth
            floor = 0.5 * float(np.sum(res(x_truth) ** 2))
            print("%-28s rounding floor (cost at the generating coefficients): ceres %.3g, scipy %.3g" % (
                p["name"], p["ceres_truth_cost"], floor))

    # The product's multi-start on the reference sky (same three starts,
    # scale fixed): both keep the lowest final cost; time of all three fits.
    import os
    ms = os.path.join(d, "multistart.txt")
    if os.path.exists(ms):
        lines = open(ms).read().split("\n")
        t_c, cost_c, win_c, cpu_c = lines[0].split()
        starts = [np.array([float(v) for v in l.split()]) for l in lines[1:] if l.strip()]
        p = json.load(open(d + "/hosek_reference_sky.json"))
        data = np.loadtxt(d + "/hosek_reference_sky.csv", delimiter=",")
        ct, g, cg, L = data[:, 0], data[:, 1], data[:, 2], data[:, 3]
        w = p["weight"]
        for method in ["trf", "lm"]:
            times, cpus = [], []
            for _ in range(repeats):
                t0, c0 = time.perf_counter(), time.process_time()
                costs = []
                for st in starts:
                    S = st[9]
                    r = least_squares(lambda x: w * (S * hosek(x, ct, g, cg)[0] - L), st[:9],
                                      jac=lambda x: w * S * hosek(x, ct, g, cg)[1], method=method,
                                      ftol=p["tolerance"], xtol=p["tolerance"],
                                      gtol=p["tolerance"], max_nfev=5000)
                    costs.append(r.cost)
                times.append(time.perf_counter() - t0)
                cpus.append(time.process_time() - c0)
            t, c = median(times), median(cpus)
            tc, cc = float(t_c), float(cpu_c)
            print("%-28s %8.3f (%7.3f) %8.3f (%7.3f) %5.1fx (%5.1fx)  %-20.12g %-20.12g %s, 3 starts (T=2,4,7): costs %s; ceres winner start %s" % (
                "hosek_reference_multistart", 1e3 * tc, 1e3 * cc, 1e3 * t, 1e3 * c, t / tc, c / cc,
                float(cost_c), min(costs), method, " ".join("%.6g" % v for v in costs), win_c))


if __name__ == "__main__":
    main()

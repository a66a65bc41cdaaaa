#!/usr/bin/env python3
"""SciPy side of bench/ceres_vs_scipy.sh: the same sky fits as
bench_ceres_fit (same samples, same start, same residuals
weight * (S F(c) - L), same analytic Jacobian, same tolerances 1e-10) with
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


def main():
    d = sys.argv[1]
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 7
    print("%-28s %10s %10s %8s  %-22s %-22s %s" % ("problem", "ceres ms", "scipy ms", "speedup",
                                                  "ceres final cost", "scipy final cost", "scipy method"))
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
            kw = dict(jac=jac, method=method, ftol=1e-10, xtol=1e-10, gtol=1e-10, max_nfev=5000)
            if method == "trf" and not fix:
                lo = np.full(nc + 1, -np.inf); lo[nc] = 0.0
                kw["bounds"] = (lo, np.full(nc + 1, np.inf))
            times = []
            for _ in range(repeats):
                t0 = time.perf_counter()
                r = least_squares(res, x0, **kw)
                times.append(time.perf_counter() - t0)
            runs.append((sorted(times)[len(times) // 2], r.cost, method, r.nfev))
        best = min(runs, key=lambda t: t[0])
        for t, cost, method, nfev in runs:
            print("%-28s %10.3f %10.3f %7.1fx  %-22.15g %-22.15g %s (%d evaluations)%s" % (
                p["name"], 1e3 * p["ceres_seconds"], 1e3 * t, t / p["ceres_seconds"],
                p["ceres_final_cost"], cost, method, nfev, "  <- fastest SciPy" if (len(runs) > 1 and t == best[0]) else ""))


if __name__ == "__main__":
    main()
